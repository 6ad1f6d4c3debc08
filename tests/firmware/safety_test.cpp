// Safety behaviour of design §8: ramp-in over 0.5 s, the host-silence watchdog (fade within 20 ms, fault
// latched), output clamped to the configured limit whatever the notes and settings.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tests/firmware/host_link.hpp"

namespace hmp::test {
namespace {

TEST(FirmwareSafety, OutputRampsInOverHalfASecond) {
  sim::SimDevice dev;
  HostLink host(dev);
  host.hello();  // default settings: ramp_in_ms = 500, gain 1
  host.play();   // handled on the next tick: ramp position 0 there
  const std::uint64_t play_tick = dev.tick() + 1;
  const TestNote n{play_tick + 3, 1500, 37.0, 0.9};
  host.notes({n});
  const std::vector<float> got = host.run(1000);
  const std::vector<float> engine = reference_output({n}, play_tick, 1000, 1000);
  for (std::size_t k = 0; k < got.size(); ++k) {
    // Independent of the firmware's arithmetic: the ramp factor k/500, capped at 1.
    const double ramp = std::min(1.0, static_cast<double>(k) / 500.0);
    ASSERT_NEAR(got[k], static_cast<double>(engine[k]) * ramp, 1e-6) << "ticks after play " << k;
  }
}

// The host plays a long note and then goes silent; the device must keep playing until the watchdog
// time has passed, then fade to exactly zero within 20 ms and latch the fault.
class FirmwareWatchdog : public ::testing::TestWithParam<std::uint32_t> {};

TEST_P(FirmwareWatchdog, HostSilenceFadesOutWithinTwentyMilliseconds) {
  const std::uint32_t hz = GetParam();
  sim::SimDevice dev(hz);
  HostLink host(dev);
  host.open_exact();
  dev.advance(1);
  host.long_note({dev.tick() + 2, 100 * hz, 45.0, 0.8});
  host.run(hz / 2);  // half a second with a live host
  host.sync(0);      // its last report arrives during this tick
  host.collect();
  const std::uint64_t last_report = dev.tick();
  const std::size_t window = hz / 4;   // 250 ms
  const std::size_t within = hz / 50;  // 20 ms
  const std::vector<float> out = dev.record(window + hz);
  float before = 0.0f;
  for (std::size_t i = window - hz / 20; i < window - 1; ++i) before = std::max(before, std::abs(out[i]));
  EXPECT_GT(before, 0.5f) << "the device must not give up early";
  for (std::size_t i = window + within; i < out.size(); ++i)
    ASSERT_EQ(out[i], 0.0f) << "tick " << last_report + 1 + i << " is " << i << " ticks after the last report";
  const Replies r = host.collect();
  ASSERT_FALSE(r.statuses.empty());
  EXPECT_NE(r.statuses.back().faults & p::fault_watchdog, 0u);
  EXPECT_EQ(r.statuses.back().state, p::State::fault);
  EXPECT_EQ(r.statuses.back().active_voices, 0u);
}

TEST_P(FirmwareWatchdog, ALiveHostKeepsItQuiet) {
  const std::uint32_t hz = GetParam();
  sim::SimDevice dev(hz);
  HostLink host(dev);
  host.hello();
  host.play();
  host.run(5 * hz);  // a Sync every 100 ms
  const p::Status s = host.status();
  EXPECT_EQ(s.faults, 0u);
  EXPECT_EQ(s.state, p::State::playing);
}

INSTANTIATE_TEST_SUITE_P(TickRates, FirmwareWatchdog, ::testing::Values(1000u, 10000u),
                         [](const auto& p) { return std::to_string(p.param) + "Hz"; });

TEST(FirmwareSafety, WatchdogTimeIsASetting) {
  sim::SimDevice dev;
  HostLink host(dev);
  host.hello();
  p::Settings s = exact_settings();
  s.watchdog_ms = 40;
  host.settings(s);
  host.play();
  dev.advance(1);
  host.long_note({dev.tick() + 2, 100000, 45.0, 0.8});
  const std::vector<float> out = dev.record(200);
  for (std::size_t i = 40 + 20; i < out.size(); ++i) ASSERT_EQ(out[i], 0.0f);
  EXPECT_NE(dev.core().faults() & p::fault_watchdog, 0u);
}

TEST(FirmwareSafety, OutputNeverExceedsTheConfiguredGain) {
  std::mt19937 rng(7);
  for (int round = 0; round < 20; ++round) {
    sim::SimDevice dev;
    HostLink host(dev);
    host.hello();
    p::Settings s;
    s.gain = std::uniform_real_distribution<float>(0.0f, 1.0f)(rng);
    s.ramp_in_ms = static_cast<std::uint16_t>(rng() % 600);
    s.policy = static_cast<p::PolicyCode>(rng() % 3);
    host.settings(s);
    host.play();
    dev.advance(1);
    // Loud, dense, overlapping notes: far more than full scale if simply added.
    std::vector<TestNote> notes;
    for (int i = 0; i < 200; ++i)
      notes.push_back({dev.tick() + 5 + static_cast<std::uint64_t>(i) * 4, static_cast<std::uint32_t>(20 + rng() % 400),
                       std::uniform_real_distribution<double>(20.0, 450.0)(rng), 1.0,
                       static_cast<std::uint8_t>(rng() % envelope::kBuiltinCount)});
    host.all_notes(notes);
    float peak = 0.0f;
    for (const float y : host.run(1500)) {
      ASSERT_TRUE(std::isfinite(y));
      ASSERT_LE(std::abs(y), s.gain);
      peak = std::max(peak, std::abs(y));
    }
    EXPECT_GT(peak, 0.5f * s.gain);  // it did play
    const p::Status st = host.status();
    EXPECT_EQ(st.faults & p::fault_output_limit, 0u);  // clamping was never needed: the limiter holds
    EXPECT_LE(std::abs(st.force_n), s.peak_force_n);
  }
}

TEST(FirmwareSafety, ZeroGainIsSilent) {
  sim::SimDevice dev;
  HostLink host(dev);
  host.hello();
  p::Settings s = exact_settings();
  s.gain = 0.0f;
  host.settings(s);
  host.play();
  host.notes({{dev.tick() + 3, 500, 100.0, 1.0}});
  for (const float y : host.run(600)) ASSERT_EQ(y, 0.0f);
}

}  // namespace
}  // namespace hmp::test
