#pragma once
// host/simulate/: a song's haptic track played on the simulated device with its plant, as `hmp sim` does
// (design §12), and how faithfully the strings' force followed the commanded vibration. No I/O here: the
// command (cli/sim_command.cpp) parses options and writes the CSV or plot.
//
// fidelity: how well the actual force follows the commanded one, insensitive to the device's fixed delay.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace hmp::simulate {

// One tick of a recording (N).
struct ForceSample {
  float commanded = 0, actual = 0, reported = 0, min_tension = 0, max_tension = 0;
};

struct Fidelity {
  std::size_t windows = 0;                             // 20 ms windows with something commanded
  double mean_ratio_error = 0, worst_ratio_error = 0;  // |rms(actual) / rms(commanded) − 1| over them
  double lag_ticks = 0;                                // the delay of actual behind commanded
};

// The delay: the lag (0 … 3 ticks) at the cross-correlation's peak, refined by a parabola through it and
// its neighbours. The ratio: RMS of the actual force over RMS of the commanded one, per 20 ms window
// where the commanded RMS is at least 5 % of `peak`, the actual taken the (rounded) delay later.
Fidelity measure_fidelity(const std::vector<ForceSample>& samples, std::uint32_t tick_hz, double peak);

}  // namespace hmp::simulate
