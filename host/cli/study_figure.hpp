#pragma once
// The PNG of `hmp study analyze --out` in the style of the paper's Figure 3: per instrument the
// first-place votes of each envelope as bars, experiment 1 and 2 side by side, the Copeland winners
// marked with a star: the analysis as grouped bars (output/bar_chart.hpp).
#include <string>
#include <vector>

#include "host/study/analysis.hpp"

namespace hmp::cli {

// Throws BadInput when `path` exists and not `force` (output/output_file.hpp's rules) or on write errors.
void write_study_figure(const std::vector<study::GroupAnalysis>& groups, const std::string& path, bool force);

}  // namespace hmp::cli
