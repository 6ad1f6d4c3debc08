#include "host/cli/study_figure.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "host/output/bar_chart.hpp"
#include "host/study/plan.hpp"

namespace hmp::cli {

using study::envelope_name;
using study::GroupAnalysis;
using study::kEnvelopes;
using study::kInstruments;
using study::mapping_of_experiment;

void write_study_figure(const std::vector<study::GroupAnalysis>& groups, const std::string& path, bool force) {
  std::vector<output::BarPanel> panels;
  for (const int experiment : {1, 2}) {
    output::BarPanel& panel = panels.emplace_back();
    panel.title = fmt::format("Experiment {} ({} mapping)", experiment, mapping_of_experiment(experiment));
    for (const char* instrument : kInstruments) {
      output::BarGroup& bars = panel.groups.emplace_back();
      bars.label = instrument;
      const auto g = std::find_if(groups.begin(), groups.end(), [&](const GroupAnalysis& a) {
        return a.experiment == experiment && a.instrument == instrument;
      });
      if (g == groups.end()) continue;  // "no data"
      for (std::size_t e = 0; e < kEnvelopes.size(); ++e) {
        bars.values.push_back(g->first_votes[e]);
        const auto& winners = g->copeland.winners;
        bars.marked.push_back(std::find(winners.begin(), winners.end(), static_cast<int>(e)) != winners.end());
      }
    }
  }
  output::BarChartSpec spec;
  for (const auto envelope : kEnvelopes) spec.series.emplace_back(envelope_name(envelope));
  spec.y_label = "first-place votes";
  spec.mark_note = "* Copeland winner (several: a tie)";
  output::write_bar_chart_png(path, panels, spec, force);  // an existing file is kept without --force
}

}  // namespace hmp::cli
