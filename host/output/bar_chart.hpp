#pragma once
// PNG of grouped bars in side-by-side panels with a legend (cairo): the study's figure
// (cli/study_figure.hpp: per instrument the first-place votes of each envelope, one panel per
// experiment). Plain data, so that what draws it knows nothing of the study.
#include <string>
#include <vector>

namespace hmp::output {

struct BarGroup {
  std::string label;           // under the group
  std::vector<double> values;  // one per series; empty: "no data"
  std::vector<bool> marked;    // a star above the bar (as many as values, or empty)
};

struct BarPanel {
  std::string title;
  std::vector<BarGroup> groups;
};

struct BarChartSpec {
  std::vector<std::string> series;  // the legend, in bar order (grey, light blue, dark blue, then again)
  std::string y_label;
  std::string mark_note;  // the legend's line for the stars
};

// Throws BadInput if the file may not be written (see output_file.hpp).
void write_bar_chart_png(const std::string& path, const std::vector<BarPanel>& panels, const BarChartSpec& spec,
                         bool force);

}  // namespace hmp::output
