#pragma once
// The plot module's interface (module "plot", host/output/plot/): the PNG pictures drawn with cairo — a
// haptic signal under its notes (signal_plot.hpp), traces on a time axis (trace_plot.hpp), grouped bars
// (bar_chart.hpp: the study's figure) and log–log panels (loglog_plot.hpp). Those headers are what the rest
// of hmp calls; they check the output file and then come here, so commands that draw nothing never load
// cairo. Errors come back as text.
#include <span>
#include <string>
#include <vector>

#include "host/output/bar_chart.hpp"
#include "host/output/loglog_plot.hpp"
#include "host/output/signal_plot.hpp"
#include "host/output/trace_plot.hpp"

namespace hmp::output {

class PlotBackend {
 public:
  static constexpr const char* kModule = "plot";
  static constexpr int kAbi = 3;

  // Each writes `path` (already checked writable) and returns "" or what went wrong.
  virtual std::string signal_png(const std::string& path, std::span<const float> samples,
                                 std::span<const PlotNote> notes, const PlotSpec& spec) const = 0;
  virtual std::string traces_png(const std::string& path, const std::vector<Trace>& traces,
                                 const TracePlotSpec& spec) const = 0;
  virtual std::string bar_chart_png(const std::string& path, const std::vector<BarPanel>& panels,
                                    const BarChartSpec& spec) const = 0;
  virtual std::string loglog_png(const std::string& path, const std::vector<LogLogPanel>& panels,
                                 const LogLogPlotSpec& spec) const = 0;

 protected:
  ~PlotBackend() = default;  // one static object in the module, never deleted through this
};

// The plot module, loaded on first use; throws BadInput naming `path` when it cannot be had.
const PlotBackend& plot_backend_for(const std::string& path);

}  // namespace hmp::output
