#pragma once
// host/output/plot/: the plot module (hmp-plot.so), everything hmp draws with cairo. Its interface is
// output/plot_backend.hpp; these are the pictures behind it. Each writes a PNG and returns "" or the error.
#include <span>
#include <string>
#include <vector>

#include "host/output/bar_chart.hpp"
#include "host/output/loglog_plot.hpp"
#include "host/output/signal_plot.hpp"
#include "host/output/trace_plot.hpp"

namespace hmp::plot {

std::string draw_signal_png(const std::string& path, std::span<const float> samples,
                            std::span<const output::PlotNote> notes, const output::PlotSpec& spec);
std::string draw_traces_png(const std::string& path, const std::vector<output::Trace>& traces,
                            const output::TracePlotSpec& spec);
std::string draw_bar_chart_png(const std::string& path, const std::vector<output::BarPanel>& panels,
                               const output::BarChartSpec& spec);
std::string draw_loglog_png(const std::string& path, const std::vector<output::LogLogPanel>& panels,
                            const output::LogLogPlotSpec& spec);

}  // namespace hmp::plot
