#pragma once
// host/plot/: the plot module (hmp-plot.so), everything hmp draws with cairo. Its interface is
// output/plot_backend.hpp; these are the pictures behind it. Each writes a PNG and returns "" or the error.
#include <span>
#include <string>
#include <vector>

#include "host/output/loglog_plot.hpp"
#include "host/output/signal_plot.hpp"
#include "host/output/trace_plot.hpp"
#include "host/study/analysis.hpp"

namespace hmp::plot {

std::string draw_signal_png(const std::string& path, std::span<const float> samples,
                            std::span<const output::PlotNote> notes, const output::PlotSpec& spec);
std::string draw_traces_png(const std::string& path, const std::vector<output::Trace>& traces,
                            const output::TracePlotSpec& spec);
std::string draw_study_figure_png(const std::string& path, const std::vector<study::GroupAnalysis>& groups);
std::string draw_loglog_png(const std::string& path, const std::vector<output::LogLogPanel>& panels,
                            const output::LogLogPlotSpec& spec);

}  // namespace hmp::plot
