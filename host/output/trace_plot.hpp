#pragma once
// PNG plot of a few traces on one time axis with a legend (cairo): e.g. the force a device was told to
// make next to the force it made (`hmp sim`). Long traces are drawn as a min/max band per pixel column,
// so the cost does not depend on their length beyond one pass over the samples.
#include <span>
#include <string>
#include <vector>

namespace hmp::output {

struct Trace {
  std::string label;
  std::span<const float> samples;  // one per 1/rate_hz
  double red = 0, green = 0, blue = 0;
};

struct TracePlotSpec {
  std::string title;
  std::string y_label = "force (N)";
  double rate_hz = 1000;  // samples per second of every trace
  double t0_s = 0;        // time of the first sample
  int width = 1600, height = 600;
};

// Throws BadInput if the file may not be written (see output_file.hpp).
void write_traces_png(const std::string& path, const std::vector<Trace>& traces, const TracePlotSpec& spec, bool force);

}  // namespace hmp::output
