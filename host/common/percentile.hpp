#pragma once
// Percentiles of measured values (latencies, frame times) for summaries and benchmarks.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace hmp {

// The p-th percentile (0–100) of `values` by nearest rank (the smallest value with at least p % of them
// at or below it); 0 when there are none.
inline double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const double rank = std::ceil(p / 100.0 * static_cast<double>(values.size()));
  const std::size_t i = rank < 1 ? 0 : static_cast<std::size_t>(rank) - 1;
  return values[std::min(i, values.size() - 1)];
}

}  // namespace hmp
