// host/simulate: the fidelity measure of `hmp sim` against signals whose answer is known by construction
// (a pure delay and gain of a sine; nothing commanded), and a track's notes clipped to a window.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "host/simulate/fidelity.hpp"
#include "host/simulate/sim_host.hpp"

namespace {

namespace sim = hmp::simulate;

// commanded = a·sin(2π f t); actual = gain·a·sin(2π f (t − delay)), at 1 kHz for `seconds`.
std::vector<sim::ForceSample> delayed(double f, double a, double gain, double delay_ticks, double seconds) {
  std::vector<sim::ForceSample> out(static_cast<std::size_t>(seconds * 1000));
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double t = static_cast<double>(i) / 1000.0;
    out[i].commanded = static_cast<float>(a * std::sin(2 * M_PI * f * t));
    out[i].actual = static_cast<float>(gain * a * std::sin(2 * M_PI * f * (t - delay_ticks / 1000.0)));
  }
  return out;
}

TEST(SimFidelity, APureGainIsTheRatioErrorInEveryWindow) {
  const sim::Fidelity f = sim::measure_fidelity(delayed(50.0, 1.0, 0.9, 0.0, 1.0), 1000, 1.0);
  EXPECT_EQ(f.windows, 50u);  // 1 s of 20 ms windows, all commanded
  EXPECT_NEAR(f.mean_ratio_error, 0.1, 1e-3);
  EXPECT_NEAR(f.worst_ratio_error, 0.1, 1e-3);
  EXPECT_NEAR(f.lag_ticks, 0.0, 1e-9);
}

TEST(SimFidelity, ADelayIsFoundBetweenTicksAndDoesNotCountAsError) {
  for (double d : {1.0, 1.3, 2.0}) {
    const sim::Fidelity f = sim::measure_fidelity(delayed(20.0, 0.5, 1.0, d, 1.0), 1000, 1.0);
    EXPECT_NEAR(f.lag_ticks, d, 0.1) << d;  // parabolic refinement of a slow sine's correlation peak
    EXPECT_LT(f.worst_ratio_error, 0.02) << d;
  }
}

TEST(SimFidelity, NothingCommandedHasNoWindows) {
  const sim::Fidelity f = sim::measure_fidelity(delayed(50.0, 0.01, 1.0, 0.0, 1.0), 1000, 1.0);  // 1% of peak
  EXPECT_EQ(f.windows, 0u);
  EXPECT_EQ(f.mean_ratio_error, 0.0);
  EXPECT_EQ(sim::measure_fidelity({}, 1000, 1.0).windows, 0u);
}

TEST(SimHostWindow, NotesAreClippedToTheWindowAndMovedToTheBase) {
  hmp::haptics::HapticTrack track;
  auto add = [&](std::uint64_t start, std::uint32_t ticks) {
    hmp::haptics::HapticNote n;
    n.note.start_tick = start;
    n.note.duration_ticks = ticks;
    track.notes.push_back(n);
  };
  add(0, 50);    // ends before the window
  add(90, 30);   // starts before it: clipped to 100 … 120
  add(150, 10);  // inside
  add(190, 40);  // runs past its end: clipped to 190 … 200
  add(200, 5);   // starts at its end
  const std::vector<hmp::synth::Note> got = sim::window_notes(track, 100, 200, 1000);
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got[0].start_tick, 1000u);
  EXPECT_EQ(got[0].duration_ticks, 20u);
  EXPECT_EQ(got[1].start_tick, 1050u);
  EXPECT_EQ(got[1].duration_ticks, 10u);
  EXPECT_EQ(got[2].start_tick, 1090u);
  EXPECT_EQ(got[2].duration_ticks, 10u);
}

}  // namespace
