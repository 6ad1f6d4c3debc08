// The PNG writers the rest of hmp calls (signal_plot.hpp, trace_plot.hpp, study/figure.hpp): check the
// output file here, draw in the plot module.
#include "host/output/plot_backend.hpp"

#include "host/common/error.hpp"
#include "host/modules/module_loader.hpp"
#include "host/output/output_file.hpp"
#include "host/study/figure.hpp"

namespace hmp::output {
namespace {

void check(const std::string& path, const std::string& error) {
  if (!error.empty()) throw BadInput(path + ": cannot write PNG: " + error);
}

}  // namespace

const PlotBackend& plot_backend_for(const std::string& path) {
  std::string why;
  const PlotBackend* backend = modules::backend<PlotBackend>(&why);
  if (backend == nullptr) throw BadInput(path + ": PNG plots need the plot module, which is not available (" + why + ")");
  return *backend;
}

void write_signal_png(const std::string& path, std::span<const float> samples, std::span<const PlotNote> notes,
                      const PlotSpec& spec, bool force) {
  check_writable(path, force);
  check(path, plot_backend_for(path).signal_png(path, samples, notes, spec));
}

void write_traces_png(const std::string& path, const std::vector<Trace>& traces, const TracePlotSpec& spec,
                      bool force) {
  check_writable(path, force);
  check(path, plot_backend_for(path).traces_png(path, traces, spec));
}

}  // namespace hmp::output

namespace hmp::study {

void write_figure(const std::vector<GroupAnalysis>& groups, const std::string& path) {
  output::check(path, output::plot_backend_for(path).study_figure_png(path, groups));
}

}  // namespace hmp::study
