// Faults of the firmware drive (design §8): what the drive senses going wrong latches a fault bit and puts
// the device in its safe state (no vibration, every string at t_min with plain stall duties) until the
// host acknowledges with Stop or Hello. Faults are injected at the board: encoder counts edited on their
// way to the core, or a motor driver that misbehaves. Tensions the motors cannot hold are refused.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/firmware/drive/drive_rig.hpp"
#include "tests/shared/spidar/spidar_reference.hpp"

namespace hmp::test {
namespace {

// A vibrating device (1 kHz, 100 Hz tone) with `inject` set as the encoder hook after 200 ms.
struct Faulted {
  explicit Faulted(sim::SimDevice::EncoderHook inject, std::size_t ticks_after = 100) {
    rig.start(exact_settings());
    rig.tone(rig.dev.tick() + 5, 5000, 100.0, 1.0);
    rig.run(200, 1.0, false);
    EXPECT_EQ(rig.dev.core().faults(), 0u) << "a fault before the injection";
    rig.dev.set_encoder_hook(std::move(inject));
    rig.run(ticks_after, 1.0, false);
  }
  void expect_safe_state() const {
    const fw::Core& core = rig.dev.core();
    EXPECT_EQ(core.state(), protocol::State::fault);
    EXPECT_EQ(rig.dev.last_output(), 0.0f) << "no vibration";
    EXPECT_EQ(core.engine().active_voices(), 0u);
    for (float d : rig.dev.duties())
      EXPECT_NEAR(static_cast<double>(d), stall_duty(static_cast<double>(exact_settings().t_min_n)), 1e-5)
          << "every string at t_min";
  }
  DriveRig rig{1000, 1};
};

TEST(DriveFaults, EncoderJumpLatchesAndGoesSafe) {
  Faulted f([](std::int32_t(&counts)[8]) { counts[5] += 5000; });  // a counter that lost 2.4 turns at once
  EXPECT_TRUE(f.rig.dev.core().faults() & protocol::fault_encoder_jump);
  f.expect_safe_state();
  // Latched: play is refused until the host acknowledges.
  f.rig.host.play();
  f.rig.run(10, 1.0, false);
  EXPECT_EQ(f.rig.dev.core().state(), protocol::State::fault);
  EXPECT_EQ(f.rig.dev.last_output(), 0.0f);
}

// Fast but possible motion is not a jump: a counter moving at 80% of the no-load speed's counts per tick.
TEST(DriveFaults, FastCounterIsNotAJump) {
  std::int32_t extra = 0;
  Faulted f(
      [&](std::int32_t(&counts)[8]) {
        if (extra < 2000) extra += 140;  // 183 counts/ms at no load
        counts[0] += extra;
      },
      5);
  EXPECT_FALSE(f.rig.dev.core().faults() & protocol::fault_encoder_jump);
}

// The counts of a grip 90 mm up, above the top motors (y = 76 mm), fed in slowly (no jump): a pose the
// device cannot have; the estimate is clamped and the fault latched.
TEST(DriveFaults, DegeneratePoseLatchesPoseDiverged) {
  const spidar_ref::Device dev = spidar_ref::x3_device();
  const spidar_ref::M3 identity = spidar_ref::axis_angle({0, 1, 0}, 0.0);
  const spidar_ref::Strings rest = spidar_ref::strings_at(dev, {0, 0, 0}, identity);
  const spidar_ref::Strings far = spidar_ref::strings_at(dev, {0, 0.09, 0}, identity);
  const double metres_per_count = 2.0 * M_PI * 0.005 / 2048.0;
  int step = 0;
  Faulted f(
      [&](std::int32_t(&counts)[8]) {
        step = std::min(step + 1, 100);
        for (int i = 0; i < 8; ++i) {
          const double change = (far.length[i] - rest.length[i]) / metres_per_count * step / 100.0;
          counts[i] += static_cast<std::int32_t>(std::lround(change));
        }
      },
      150);
  EXPECT_TRUE(f.rig.dev.core().faults() & protocol::fault_pose_diverged);
  EXPECT_FALSE(f.rig.dev.core().faults() & protocol::fault_encoder_jump) << "fed in below the jump limit";
  f.expect_safe_state();
}

// A motor driver that reels string out (a wiring fault, a broken H-bridge): its string goes slack and the
// drive notices from the lengths (the paid-out string is longer than its straight path).
TEST(DriveFaults, ReelingOutMotorLatchesStringSlack) {
  DriveRig rig(1000, 1);
  rig.start(exact_settings());
  rig.tone(rig.dev.tick() + 5, 5000, 100.0, 0.5);
  rig.run(200, 1.0, false);
  rig.dev.set_duty_hook([](float(&duty)[8]) { duty[3] = -0.3f; });
  bool plant_slack = false;
  rig.dev.set_plant_observer(
      [&](double, const sim::plant::PlantOutput& out) { plant_slack = plant_slack || !(out.taut & 8u); });
  rig.run(200, 1.0, false);
  EXPECT_TRUE(plant_slack) << "the injected fault did slacken the string";
  EXPECT_TRUE(rig.dev.core().faults() & protocol::fault_string_slack);
  EXPECT_EQ(rig.dev.core().state(), protocol::State::fault);
  EXPECT_EQ(rig.dev.last_output(), 0.0f);
}

// Stop acknowledges the faults; with the cause gone (the driver repaired, the string reeled back in at
// t_min) the drive renders again.
TEST(DriveFaults, StopClearsAndTheDriveRecovers) {
  DriveRig rig(1000, 1);
  rig.start(exact_settings());
  rig.run(100, 1.0, false);
  rig.dev.set_duty_hook([](float(&duty)[8]) { duty[3] = -0.3f; });
  rig.run(30, 1.0, false);  // reeling out at ~0.8 m/s: a few mm of slack
  ASSERT_TRUE(rig.dev.core().faults() & protocol::fault_string_slack);
  rig.dev.set_duty_hook({});
  rig.run(1000, 1.0, false);  // safe state: stall duties at t_min reel the slack in (~0.1 m/s)
  rig.host.transport(protocol::TransportOp::stop);
  rig.run(50, 1.0, false);
  EXPECT_EQ(rig.dev.core().faults(), 0u);
  rig.host.play();
  rig.tone(rig.dev.tick() + 5, 400, 100.0, 1.0);
  rig.trace.on = true;
  rig.run(300, 1.0, true);
  EXPECT_EQ(rig.dev.core().faults(), 0u);
  EXPECT_EQ(rig.dev.core().state(), protocol::State::playing);
  const Sinusoid a = fit_sinusoid(rig.trace.t, rig.trace.force, 100.0);
  EXPECT_GT(a.amplitude, 0.5) << "vibrating again";
}

// Settings whose tensions the motors cannot hold (the protocol allows 20 N; the stall tension is 7.9 N)
// are refused with bad_value and change nothing: accepted, every motor would sit at full duty, also in the
// safe state. Up to the drive's margin they are taken.
TEST(DriveFaults, TensionsBeyondWhatTheMotorsHoldAreRefused) {
  DriveRig rig{1000, 1};
  rig.start(exact_settings());
  rig.run(50, 1.0, false);
  const float most = rig.dev.core().drive().max_tension_n();
  const double stall = 1.0 / stall_duty(1.0);  // the tension a duty of 1 holds at standstill
  EXPECT_NEAR(static_cast<double>(most), 0.8 * stall, 1e-3);
  EXPECT_GE(most, exact_settings().t_max_n) << "the default bounds must stay accepted";
  rig.host.collect();
  protocol::Settings s = exact_settings();
  s.t_min_n = 19.0f;
  s.t_max_n = 20.0f;
  const std::uint16_t seq = rig.host.settings(s);
  rig.run(50, 1.0, false);
  const Replies r = rig.host.collect();
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_EQ(r.errors[0].code, protocol::ErrorCode::bad_value);
  EXPECT_EQ(r.errors[0].seq, seq);
  for (float d : rig.dev.duties()) EXPECT_LT(std::fabs(d), 0.5f) << "the refused tensions were applied";
  s.t_min_n = 1.0f;
  s.t_max_n = most;
  rig.host.settings(s);
  rig.run(50, 1.0, false);
  EXPECT_TRUE(rig.host.collect().errors.empty());
}

// A board without motors (the QEMU board, the default SimDevice): no drive, the vibration value as before,
// Status.force_n = output × peak force.
TEST(DriveFaults, BoardWithoutMotorsSkipsTheDrive) {
  sim::SimDevice dev;
  HostLink host(dev);
  EXPECT_FALSE(dev.core().has_drive());
  EXPECT_EQ(dev.plant(), nullptr);
  protocol::Settings s = exact_settings();
  s.peak_force_n = 3.0f;
  host.hello();
  host.settings(s);
  host.play();
  TestNote n;
  n.start = dev.tick() + 3;
  n.duration = 100;
  host.long_note(n);
  dev.advance(20);
  const protocol::Status st = dev.core().status();
  EXPECT_NE(st.output, 0.0f);
  EXPECT_FLOAT_EQ(st.force_n, st.output * 3.0f);
}

}  // namespace
}  // namespace hmp::test
