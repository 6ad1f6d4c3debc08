// The firmware drive in closed loop with the plant (design §8, §11, §12): the force the strings put on the
// grip follows the commanded vibration, the strings stay taut and below t_max, and the watchdog and the
// emergency stop bring the force back to the bias within 20 ms. The reference is the commanded samples
// themselves; the measurement is the plant's physical string force, fitted in double precision.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/firmware/drive/drive_rig.hpp"

namespace hmp::test {
namespace {

constexpr double kMaxAmplitudeError = 0.05;

void expect_follows(std::uint32_t tick_hz, double hz) {
  const ToneResult r = measure_tone(tick_hz, hz, 1.0);
  print_tone(tick_hz >= 10000 ? "10 kHz tick" : " 1 kHz tick", hz, r);
  EXPECT_NEAR(r.commanded, 1.0, 1e-3) << "the commanded vibration is full scale × 1 N";
  EXPECT_LE(std::fabs(r.error), kMaxAmplitudeError) << hz << " Hz at " << tick_hz << " Hz tick";
  EXPECT_TRUE(r.taut) << "a string went slack";
  EXPECT_GT(r.min_tension, 0.05);
  EXPECT_LE(r.max_tension, exact_settings().t_max_n);
  EXPECT_EQ(r.faults, 0u);
  EXPECT_FALSE(r.unstable);
  // The delay is the reference model's (about 1.2 ticks) plus the plant's residue: bounded, not growing.
  EXPECT_GT(r.lag_ms, 0.0);
  EXPECT_LT(r.lag_ms, 2.0e3 / tick_hz);
  testing::Test::RecordProperty("lag_ms_" + std::to_string(static_cast<int>(hz)), std::to_string(r.lag_ms));
}

TEST(DriveClosedLoop, FollowsVibrationAt1kHzTick) {
  for (double hz : {50.0, 100.0, 250.0}) expect_follows(1000, hz);
}

TEST(DriveClosedLoop, FollowsVibrationAt10kHzTick) {
  for (double hz : {50.0, 100.0, 250.0}) expect_follows(10000, hz);
}

// The measurement can tell: without the compensation the 225 Hz motor/string resonance and the motors
// that must follow the grip make the force far off (docs/spidar.md).
TEST(DriveClosedLoop, WithoutCompensationTheForceIsOff) {
  sim::SimOptions o;
  o.drive.compensator.enabled = false;
  const ToneResult low = measure_tone(1000, 50.0, 1.0, o);
  const ToneResult high = measure_tone(1000, 250.0, 1.0, o);
  print_tone("uncompensated", 50.0, low);
  print_tone("uncompensated", 250.0, high);
  EXPECT_GT(std::fabs(low.error), 0.2);
  EXPECT_GT(std::fabs(high.error), kMaxAmplitudeError);
}

// A larger vibration on a different direction: still within 5%, the status reports the force.
TEST(DriveClosedLoop, PeakForceAndStatus) {
  protocol::Settings s = exact_settings();
  s.peak_force_n = 2.0f;
  const ToneResult r = measure_tone(1000, 100.0, 0.8, {}, s);
  print_tone("2 N peak, 0.8 amplitude", 100.0, r);
  EXPECT_NEAR(r.commanded, 1.6, 2e-3);
  EXPECT_LE(std::fabs(r.error), kMaxAmplitudeError);
  EXPECT_TRUE(r.taut);

  DriveRig rig(1000);
  rig.start(s);
  rig.tone(rig.dev.tick() + 5, 400, 100.0, 0.8);
  rig.run(200, s.peak_force_n, false);
  for (int i = 0; i < 50; ++i) {
    rig.run(1, s.peak_force_n, false);
    // Status.force_n: what the QP's tensions make along the direction; the request is output × peak.
    const protocol::Status st = rig.dev.core().status();
    EXPECT_NEAR(st.force_n, st.output * s.peak_force_n, 0.01) << "tick " << st.tick;
  }
}

// The force the strings make before any vibration (the bias), then after a vibration stops.
struct StopResult {
  double bias = 0;
  double worst_after_20ms = 0;  // |F − bias| from 20 ms after the stop on
  std::uint32_t faults = 0;
};

template <class StopFn>
StopResult stop_and_watch(std::uint32_t tick_hz, StopFn stop, sim::SimOptions options = {}) {
  DriveRig rig(tick_hz, 1, options);
  const protocol::Settings s = exact_settings();
  rig.start(s);
  rig.trace.on = true;
  rig.run(tick_hz / 5, s.peak_force_n, false);  // settle at the bias
  StopResult out;
  double sum = 0;
  const std::size_t n0 = rig.trace.force.size() / 2;
  for (std::size_t i = n0; i < rig.trace.force.size(); ++i) sum += rig.trace.force[i];
  out.bias = sum / static_cast<double>(rig.trace.force.size() - n0);
  rig.tone(rig.dev.tick() + 5, 10 * tick_hz, 100.0, 1.0);
  rig.run(tick_hz / 5, s.peak_force_n, false);
  const double t_stop = stop(rig);  // plant time at which the stop takes effect
  rig.trace.t.clear();
  rig.trace.force.clear();
  for (std::size_t i = 0; i < tick_hz / 10; ++i) rig.dev.advance(1);  // the host says nothing now
  for (std::size_t i = 0; i < rig.trace.t.size(); ++i) {
    if (rig.trace.t[i] >= t_stop + 0.020)
      out.worst_after_20ms = std::max(out.worst_after_20ms, std::fabs(rig.trace.force[i] - out.bias));
  }
  out.faults = rig.dev.core().faults();
  return out;
}

TEST(DriveClosedLoop, WatchdogBringsTheForceToTheBiasWithin20ms) {
  for (std::uint32_t tick_hz : {1000u, 10000u}) {
    const StopResult r = stop_and_watch(tick_hz, [](DriveRig& rig) {
      // The host goes silent: advance until the watchdog trips (state fault), noting when.
      while (rig.dev.core().state() != protocol::State::fault) rig.dev.advance(1);
      return rig.dev.plant()->time();
    });
    std::printf("watchdog, %u Hz tick: bias %.4f N, worst |F - bias| 20 ms after the trip %.4f N\n", tick_hz, r.bias,
                r.worst_after_20ms);
    EXPECT_TRUE(r.faults & protocol::fault_watchdog);
    EXPECT_LT(std::fabs(r.bias), 0.02) << "the bias tensions make (almost) no force";
    EXPECT_LT(r.worst_after_20ms, 0.02) << "2% of the 1 N peak";
  }
}

TEST(DriveClosedLoop, EmergencyStopBringsTheForceToTheBiasWithin20ms) {
  for (std::uint32_t tick_hz : {1000u, 10000u}) {
    const StopResult r = stop_and_watch(tick_hz, [](DriveRig& rig) {
      const double t = rig.dev.plant()->time();
      rig.host.estop();
      return t;
    });
    std::printf("estop, %u Hz tick: worst |F - bias| 20 ms after the stop %.4f N\n", tick_hz, r.worst_after_20ms);
    EXPECT_TRUE(r.faults & protocol::fault_estop);
    EXPECT_LT(r.worst_after_20ms, 0.02);
  }
}

// The split drive (firmware/drive.hpp; the STM32F407's 10 kHz tick): pose and QP at 1 kHz outside the
// tick, tensions along the planned lines, compensation and duties every 0.1 ms. Issue goal: within 2% at
// 500 Hz and 1 kHz, which a 1 kHz drive cannot reach at all (its output stops at 500 Hz). 0.5 N: at 1 N and
// 1 kHz a string goes slack from the 0.3 N bias — whole or split (docs/spidar.md, "Split drive").
TEST(DriveClosedLoop, SplitDriveAt10kHzFollowsUpTo1kHz) {
  sim::SimOptions split;
  split.drive.plan_hz = 1000;
  for (double hz : {50.0, 250.0, 500.0, 1000.0}) {
    const ToneResult r = measure_tone(10000, hz, 0.5, split);
    print_tone("split, 10 kHz tick", hz, r);
    EXPECT_NEAR(r.commanded, 0.5, 1e-3);
    EXPECT_LE(std::fabs(r.error), 0.02) << hz << " Hz";
    EXPECT_TRUE(r.taut) << hz << " Hz";
    EXPECT_EQ(r.faults, 0u);
    EXPECT_FALSE(r.unstable);
  }
}

TEST(DriveClosedLoop, SplitDriveStopsWithin20ms) {
  sim::SimOptions split;
  split.drive.plan_hz = 1000;
  const StopResult w = stop_and_watch(
      10000,
      [](DriveRig& rig) {
        while (rig.dev.core().state() != protocol::State::fault) rig.dev.advance(1);
        return rig.dev.plant()->time();
      },
      split);
  EXPECT_TRUE(w.faults & protocol::fault_watchdog);
  EXPECT_LT(w.worst_after_20ms, 0.02);
  const StopResult e = stop_and_watch(
      10000,
      [](DriveRig& rig) {
        const double t = rig.dev.plant()->time();
        rig.host.estop();
        return t;
      },
      split);
  EXPECT_TRUE(e.faults & protocol::fault_estop);
  EXPECT_LT(e.worst_after_20ms, 0.02);
}

}  // namespace
}  // namespace hmp::test
