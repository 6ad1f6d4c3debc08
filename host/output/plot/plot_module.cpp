// The plot module's entry (hmp-plot.so): the PlotBackend over the cairo drawings.
#include "host/modules/module_loader.hpp"
#include "host/output/plot_backend.hpp"
#include "host/output/plot/drawings.hpp"

namespace hmp::plot {
namespace {

class CairoBackend final : public output::PlotBackend {
 public:
  std::string signal_png(const std::string& path, std::span<const float> samples,
                         std::span<const output::PlotNote> notes, const output::PlotSpec& spec) const override {
    return draw_signal_png(path, samples, notes, spec);
  }
  std::string traces_png(const std::string& path, const std::vector<output::Trace>& traces,
                         const output::TracePlotSpec& spec) const override {
    return draw_traces_png(path, traces, spec);
  }
  std::string bar_chart_png(const std::string& path, const std::vector<output::BarPanel>& panels,
                            const output::BarChartSpec& spec) const override {
    return draw_bar_chart_png(path, panels, spec);
  }
  std::string loglog_png(const std::string& path, const std::vector<output::LogLogPanel>& panels,
                         const output::LogLogPlotSpec& spec) const override {
    return draw_loglog_png(path, panels, spec);
  }
};

}  // namespace
}  // namespace hmp::plot

HMP_DEFINE_MODULE(hmp::output::PlotBackend, hmp::plot::CairoBackend)
