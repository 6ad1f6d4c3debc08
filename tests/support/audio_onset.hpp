#pragma once
// Where a note's sound starts in a recording of the virtual sound card (per frame: |left| + |right|),
// for the measurements of audio against haptic onsets (bench e2e-timing, tests/e2e/play_speed_test).
#include <algorithm>
#include <cstdint>
#include <vector>

namespace hmp::test {

// First frame at −60 dB of the peak of the 130 ms from `around` − 30 ms, searched from there; −1 when
// there is no sound, or when what comes before is not silent enough (under a tenth of the threshold
// over the 30 ms before the search) for the first crossing to be this note's.
inline std::int64_t onset_frame(const std::vector<float>& level, std::int64_t around, int rate) {
  const std::int64_t ms30 = 30 * rate / 1000;
  if (around - 2 * ms30 < 0) return -1;
  const auto from = static_cast<std::size_t>(around - ms30);
  const std::size_t end = std::min(level.size(), from + static_cast<std::size_t>(130 * rate / 1000));
  float peak = 0, before = 0;
  for (std::size_t i = from; i < end; ++i) peak = std::max(peak, level[i]);
  for (std::size_t i = from - static_cast<std::size_t>(ms30); i < from; ++i) before = std::max(before, level[i]);
  const float threshold = 1e-3f * peak;
  if (!(peak > 0) || before >= 0.1f * threshold) return -1;
  std::size_t i = from;
  while (i < end && level[i] < threshold) ++i;
  return static_cast<std::int64_t>(i);
}

}  // namespace hmp::test
