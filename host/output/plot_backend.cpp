// The PNG writers the rest of hmp calls (signal_plot.hpp, trace_plot.hpp, bar_chart.hpp, loglog_plot.hpp):
// check the output file here, draw in the plot module.
#include "host/output/plot_backend.hpp"

#include "host/common/error.hpp"
#include "host/modules/module_loader.hpp"
#include "host/output/output_file.hpp"

namespace hmp::output {
namespace {

void check(const std::string& path, const std::string& error) {
  if (!error.empty()) throw BadInput(path + ": cannot write PNG: " + error);
}

// The module draws into PATH.part; renamed to PATH once the PNG is whole (output_file.hpp).
template <class Draw>
void write_png(const std::string& path, bool force, Draw draw) {
  check_writable(path, force);
  const PlotBackend& backend = plot_backend_for(path);
  StagedOutput staged(path);
  check(path, draw(backend, staged.part()));
  staged.commit();
}

}  // namespace

const PlotBackend& plot_backend_for(const std::string& path) {
  std::string why;
  const PlotBackend* backend = modules::backend<PlotBackend>(&why);
  if (backend == nullptr)
    throw BadInput(path + ": PNG plots need the plot module, which is not available (" + why + ")");
  return *backend;
}

void write_signal_png(const std::string& path, std::span<const float> samples, std::span<const PlotNote> notes,
                      const PlotSpec& spec, bool force) {
  write_png(path, force,
            [&](const PlotBackend& b, const std::string& to) { return b.signal_png(to, samples, notes, spec); });
}

void write_traces_png(const std::string& path, const std::vector<Trace>& traces, const TracePlotSpec& spec,
                      bool force) {
  write_png(path, force, [&](const PlotBackend& b, const std::string& to) { return b.traces_png(to, traces, spec); });
}

void write_loglog_png(const std::string& path, const std::vector<LogLogPanel>& panels, const LogLogPlotSpec& spec,
                      bool force) {
  write_png(path, force, [&](const PlotBackend& b, const std::string& to) { return b.loglog_png(to, panels, spec); });
}

void write_bar_chart_png(const std::string& path, const std::vector<BarPanel>& panels, const BarChartSpec& spec,
                         bool force) {
  write_png(path, force,
            [&](const PlotBackend& b, const std::string& to) { return b.bar_chart_png(to, panels, spec); });
}

}  // namespace hmp::output
