#pragma once
// PNG plot of a haptic signal (cairo): a piano-roll strip of the notes above the waveform, on a shared
// time axis, so a person can see what they will feel. Long signals are drawn as a min/max band per
// pixel column, so the cost does not depend on the song's length beyond one pass over the samples.
#include <cstdint>
#include <span>
#include <string>
#include "shared/synth/tick_rate.hpp"

namespace hmp::output {

struct PlotNote {
  double start_s = 0, end_s = 0;
  int key = 60;
};

struct PlotSpec {
  std::string title;
  std::uint32_t tick_hz = synth::kNominalTickHz;
  std::uint64_t first_tick = 0;
  int width = 1600, height = 700;
};

void write_signal_png(const std::string& path, std::span<const float> samples, std::span<const PlotNote> notes,
                      const PlotSpec& spec, bool force);

}  // namespace hmp::output
