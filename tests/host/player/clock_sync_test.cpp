// ClockSync (host/player/clock_sync.hpp) against a simulated device clock written here: position(h) =
// p0 + rate·(h − h0) ticks at host µs h, the Sync arriving half its transit after it left, the reply
// leaving on the next tick (after the (1 − sub-tick) hold) and coming back in the other half. The
// loaded-host tests add what a busy machine does to the exchanges (see LoadedHost below).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <random>
#include <vector>

#include "host/player/clock_sync.hpp"

namespace {

using hmp::player::ClockSync;
using hmp::player::SyncSample;
using Verdict = ClockSync::Verdict;

// The device reads its clock at `pos` as the Sync arrives (host time `arrival`), answers on its next
// tick and the reply takes `down_us` back.
SyncSample reading(std::int64_t sent_us, double arrival, double pos, double ticks_per_us, double down_us) {
  const double tick = std::floor(pos);
  const double fraction = pos - tick;
  const double hold_us = (1.0 - fraction) / ticks_per_us;  // handled on the next tick
  SyncSample s;
  s.sent_us = sent_us;
  s.received_us = static_cast<std::int64_t>(std::llround(arrival + hold_us + down_us));
  s.tick = static_cast<std::uint64_t>(tick);
  // At most 2^32 − 2: 2^32 − 1 is the overdue marker, which a timer read never gives.
  s.subtick = static_cast<std::uint32_t>(std::min(fraction * 4294967296.0, 4294967294.0));
  return s;
}

struct FakeDevice {
  double p0 = 1000.25;  // ticks at host time h0
  std::int64_t h0 = 5'000'000;
  double ticks_per_us = 1e-3;  // 1 kHz × (1 + drift)

  double position(double host_us) const { return p0 + ticks_per_us * (host_us - static_cast<double>(h0)); }

  // A Sync sent at `sent_us` whose trip to the device takes `up_us` and back `down_us`.
  SyncSample exchange(std::int64_t sent_us, double up_us, double down_us) const {
    const double arrival = static_cast<double>(sent_us) + up_us;
    return reading(sent_us, arrival, position(arrival), ticks_per_us, down_us);
  }
};

ClockSync::Options at_1khz() {
  ClockSync::Options o;
  o.tick_hz = 1000;
  return o;
}

TEST(PlayerClockSync, NothingKnownBeforeTheFirstSample) {
  const ClockSync c(at_1khz());
  EXPECT_FALSE(c.position(0).has_value());
  EXPECT_FALSE(c.tick_at(0).has_value());
  EXPECT_FALSE(c.ready());
}

TEST(PlayerClockSync, SymmetricTransitGivesTheExactOffset) {
  FakeDevice dev;
  ClockSync c(at_1khz());
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(c.add(dev.exchange(dev.h0 + i * 3'100, 150.0, 150.0)), ClockSync::Verdict::used);
  }
  ASSERT_TRUE(c.ready());
  for (const double h : {5e6, 5.5e6, 6e6, 9e6}) {
    // The received time is rounded to whole µs: ≤ 0.5 µs of error on half of it → ≤ 0.25e-3 ticks.
    EXPECT_NEAR(*c.position(static_cast<std::int64_t>(h)), dev.position(h), 1e-3) << h;
  }
}

TEST(PlayerClockSync, DriftIsFittedOnceTheSamplesSpanTwoSeconds) {
  for (const double ppm : {-800.0, -50.0, 0.0, 120.0}) {
    FakeDevice dev;
    dev.ticks_per_us = 1e-3 * (1.0 + ppm * 1e-6);
    ClockSync c(at_1khz());
    for (int i = 0; i < 40; ++i) c.add(dev.exchange(dev.h0 + i * 100'000, 200.0, 200.0));  // 4 s
    EXPECT_TRUE(c.drift_fitted());
    EXPECT_NEAR(c.drift() * 1e6, ppm, 1.0) << ppm;
    // 200 ms beyond the last sample (the lookahead) the prediction still holds.
    const double h = static_cast<double>(dev.h0) + 4.1e6;
    EXPECT_NEAR(*c.position(static_cast<std::int64_t>(h)), dev.position(h), 2e-3) << ppm;
  }
}

TEST(PlayerClockSync, ShortSpanKeepsTheNominalRate) {
  FakeDevice dev;
  dev.ticks_per_us = 1e-3 * (1.0 + 500e-6);
  ClockSync c(at_1khz());
  for (int i = 0; i < 10; ++i) c.add(dev.exchange(dev.h0 + i * 10'000, 100.0, 100.0));  // 0.1 s
  EXPECT_FALSE(c.drift_fitted());
  EXPECT_DOUBLE_EQ(c.drift(), 0.0);
}

TEST(PlayerClockSync, QuickestSamplesWinOverDelayedOnes) {
  // Every exchange has 100 µs each way; a random half is held up by up to 5 ms more on one leg (a busy
  // host, a USB frame missed). The fit must follow the quick ones.
  FakeDevice dev;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> extra(0.0, 5000.0);
  std::bernoulli_distribution delayed(0.5);
  ClockSync c(at_1khz());
  for (int i = 0; i < 64; ++i) {
    const double up = 100.0 + (delayed(rng) ? extra(rng) : 0.0);
    const double down = 100.0 + (delayed(rng) ? extra(rng) : 0.0);
    c.add(dev.exchange(dev.h0 + i * 100'000, up, down));
  }
  const double h = static_cast<double>(dev.h0) + 6.5e6;
  EXPECT_NEAR(*c.position(static_cast<std::int64_t>(h)), dev.position(h), 0.02);
  EXPECT_NEAR(c.best_transit_us(), 200.0, 1.0);
}

TEST(PlayerClockSync, AsymmetricTransitErrsByHalfTheDifference) {
  // The one thing a round trip cannot tell: 300 µs up and 100 µs down look like 200 + 200, so the
  // Sync is believed to arrive 100 µs before it did and the estimated device clock reads 0.1 tick
  // ahead. Checked so the documented limit stays true.
  FakeDevice dev;
  ClockSync c(at_1khz());
  for (int i = 0; i < 8; ++i) c.add(dev.exchange(dev.h0 + i * 1000, 300.0, 100.0));
  const double h = static_cast<double>(dev.h0) + 1e5;
  EXPECT_NEAR(*c.position(static_cast<std::int64_t>(h)) - dev.position(h), 0.1, 2e-3);
}

TEST(PlayerClockSync, TickGoingBackMeansTheDeviceRestarted) {
  FakeDevice dev;
  ClockSync c(at_1khz());
  for (int i = 0; i < 8; ++i) c.add(dev.exchange(dev.h0 + i * 10'000, 100.0, 100.0));
  FakeDevice rebooted = dev;
  rebooted.p0 = 3.5;
  rebooted.h0 = dev.h0 + 100'000;
  EXPECT_EQ(c.add(rebooted.exchange(rebooted.h0, 100.0, 100.0)), ClockSync::Verdict::reset);
  EXPECT_EQ(c.resets(), 1u);
  for (int i = 1; i < 8; ++i)
    EXPECT_EQ(c.add(rebooted.exchange(rebooted.h0 + i * 10'000, 100.0, 100.0)), ClockSync::Verdict::used);
  const double h = static_cast<double>(rebooted.h0) + 2e5;
  EXPECT_NEAR(*c.position(static_cast<std::int64_t>(h)), rebooted.position(h), 1e-3);
}

TEST(PlayerClockSync, LostTicksAreAStepOnceASecondSampleConfirmsThem) {
  FakeDevice dev;
  ClockSync c(at_1khz());
  for (int i = 0; i < 8; ++i) c.add(dev.exchange(dev.h0 + i * 10'000, 100.0, 100.0));
  FakeDevice lagging = dev;
  lagging.p0 -= 20.0;  // an emulator that missed 20 tick interrupts
  // The first sample off the line waits aside; the fit still follows the old clock.
  EXPECT_EQ(c.add(lagging.exchange(dev.h0 + 90'000, 100.0, 100.0)), Verdict::held);
  EXPECT_NEAR(*c.position(dev.h0 + 95'000), dev.position(static_cast<double>(dev.h0) + 95e3), 1e-3);
  EXPECT_EQ(c.add(lagging.exchange(dev.h0 + 100'000, 100.0, 100.0)), Verdict::step);
  EXPECT_EQ(c.resets(), 0u);
  EXPECT_EQ(c.steps(), 1u);
  EXPECT_EQ(c.samples(), 2u);  // the held sample and the one that confirmed it
  for (int i = 11; i < 16; ++i) c.add(lagging.exchange(dev.h0 + i * 10'000, 100.0, 100.0));
  const double h = static_cast<double>(dev.h0) + 3e5;
  EXPECT_NEAR(*c.position(static_cast<std::int64_t>(h)), lagging.position(h), 1e-3);
  // A small wobble within the threshold is not a step.
  EXPECT_EQ(c.add(lagging.exchange(dev.h0 + 170'000, 100.0, 2100.0)), Verdict::used);
}

TEST(PlayerClockSync, OneWrongSampleIsDroppedNotAStep) {
  // A reading 30 ticks off that the next one does not confirm (a corrupted exchange): never fitted.
  FakeDevice dev;
  ClockSync c(at_1khz());
  for (int i = 0; i < 8; ++i) c.add(dev.exchange(dev.h0 + i * 10'000, 100.0, 100.0));
  FakeDevice wrong = dev;
  wrong.p0 += 30.0;
  EXPECT_EQ(c.add(wrong.exchange(dev.h0 + 80'000, 100.0, 100.0)), Verdict::held);
  EXPECT_EQ(c.add(dev.exchange(dev.h0 + 90'000, 100.0, 100.0)), Verdict::used);
  EXPECT_EQ(c.samples(), 9u);
  // Even a second reading like the dropped one is only held again: it has nothing to agree with.
  EXPECT_EQ(c.add(wrong.exchange(dev.h0 + 100'000, 100.0, 100.0)), Verdict::held);
  EXPECT_EQ(c.add(dev.exchange(dev.h0 + 110'000, 100.0, 100.0)), Verdict::used);
  EXPECT_EQ(c.steps(), 0u);
  const double h = static_cast<double>(dev.h0) + 3e5;
  EXPECT_NEAR(*c.position(static_cast<std::int64_t>(h)), dev.position(h), 1e-3);
}

TEST(PlayerClockSync, SampleTooWideToTellNeitherConfirmsNorDropsAHeldOne) {
  FakeDevice dev;
  ClockSync c(at_1khz());
  for (int i = 0; i < 8; ++i) c.add(dev.exchange(dev.h0 + i * 100'000, 100.0, 100.0));
  FakeDevice lagging = dev;
  lagging.p0 -= 12.0;
  EXPECT_EQ(c.add(lagging.exchange(dev.h0 + 800'000, 100.0, 100.0)), Verdict::held);
  // 30 ms on the way there: the arrival is known to ±15 ticks, which fits the old line and the new
  // one alike.
  EXPECT_EQ(c.add(lagging.exchange(dev.h0 + 900'000, 30'000.0, 100.0)), Verdict::used);
  EXPECT_EQ(c.add(lagging.exchange(dev.h0 + 1'000'000, 100.0, 100.0)), Verdict::step);
}

TEST(PlayerClockSync, TickAtRoundsHalvesUpAndKeepsLargeCountsExact) {
  FakeDevice dev;
  dev.p0 = 1099511627776.0;  // 2^40 ticks: beyond what a double holds to 1e-3 tick absolutely
  ClockSync c(at_1khz());
  for (int i = 0; i < 8; ++i) c.add(dev.exchange(dev.h0 + i * 1000, 0.0, 0.0));
  // position(h0 + 400 µs) = 2^40 + 0.4 → 2^40; + 600 µs → 2^40 + 1; +1500 µs = 2^40 + 1.5 → 2^40 + 2.
  EXPECT_EQ(*c.tick_at(dev.h0 + 400), 1099511627776u);
  EXPECT_EQ(*c.tick_at(dev.h0 + 600), 1099511627777u);
  EXPECT_EQ(*c.tick_at(dev.h0 + 1600), 1099511627778u);
  // Before tick 0 there is none.
  FakeDevice young;
  young.p0 = 0.5;
  ClockSync d(at_1khz());
  d.add(young.exchange(young.h0, 0.0, 0.0));
  EXPECT_EQ(*d.tick_at(young.h0 - 10'000), 0u);
}

TEST(PlayerClockSync, HostTimeAtIsTheInverse) {
  FakeDevice dev;
  dev.ticks_per_us = 1e-3 * (1.0 + 300e-6);
  ClockSync c(at_1khz());
  for (int i = 0; i < 30; ++i) c.add(dev.exchange(dev.h0 + i * 100'000, 50.0, 50.0));
  for (const double ticks : {1000.0, 2500.5, 4321.0}) {
    const double h = *c.host_us_at(ticks);
    EXPECT_NEAR(*c.position(static_cast<std::int64_t>(std::llround(h))), ticks, 2e-3);
  }
}

// What a busy host (both cores loaded, e.g. a parallel build) does to the Sync exchanges, as recorded on
// the real-time simulated device (docs/player.md, Clock sync). In stretches of load a run of exchanges
// waits 1–20 ms on one leg (the host thread descheduled between the send and the device, or between
// the reply and its timestamp), and the device's tick interrupt runs late: some Syncs arrive while a tick
// is overdue (sub-tick saturated, tick count behind by 1–12 ticks, often by the same amount several
// times in a row). Every timestamp jitters by a few µs; outside the loaded stretches the legs take 30–75 µs.
struct LoadedHost {
  bool host_delays = true;
  bool overdue_ticks = true;
  std::mt19937 rng{11};
  bool delayed = false;  // the previous exchange was: delays come in runs
  bool overdue = false;
  int lag = 0;

  static bool loaded(double t_s) {
    return (t_s >= 3 && t_s < 6) || (t_s >= 9 && t_s < 12) || (t_s >= 14 && t_s < 17) || (t_s >= 22.5 && t_s < 25.5);
  }
  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
  bool chance(double p) { return std::bernoulli_distribution(p)(rng); }
  std::int64_t jitter() { return std::uniform_int_distribution<std::int64_t>(-3, 3)(rng); }

  // `clock(host_us)`: the device's true position.
  template <class Clock>
  SyncSample exchange(const Clock& clock, double ticks_per_us, std::int64_t sent_us, double t_s) {
    double up = uniform(30.0, 75.0), down = uniform(30.0, 75.0);
    delayed = host_delays && loaded(t_s) && chance(delayed ? 0.6 : 0.3);
    if (delayed) (chance(0.5) ? up : down) += uniform(1000.0, 20'000.0);
    overdue = overdue_ticks && loaded(t_s) && chance(overdue ? 0.6 : 0.25);
    const double arrival = static_cast<double>(sent_us) + up;
    SyncSample s;
    if (overdue) {
      if (lag == 0 || chance(0.5)) lag = std::uniform_int_distribution<int>(1, 12)(rng);
      s.sent_us = sent_us;
      s.tick = static_cast<std::uint64_t>(std::floor(clock(arrival))) - static_cast<std::uint64_t>(lag);
      s.subtick = ClockSync::kOverdueSubtick;
      // Answered as soon as the device catches up, not on a tick boundary.
      s.received_us = std::llround(arrival + uniform(0.0, 30.0) + down);
    } else {
      s = reading(sent_us, arrival, clock(arrival), ticks_per_us, down);
    }
    s.sent_us += jitter();
    s.received_us += jitter();
    return s;
  }
};

struct LoadedRun {
  double worst_ticks = 0.0;  // largest |estimated − true position| the player would have scheduled with
  int step_seen_at = 0;      // the step verdict came with the n-th sample after the clock stepped (1 = first)
  int reset_seen_at = 0;
  int held = 0;
  std::uint64_t steps = 0, resets = 0;
  double drift = 0.0;
};

// 30 s of Syncs (8 at 3 ms, then one every 100 ms) with a device drifting +80 ppm that loses 15 ticks
// at 19.05 s (an emulator) and restarts at 27.05 s, both in a quiet stretch. Every 10 ms of host time h,
// with the samples received by then: the position the player would ask for, at h + 200 ms (its
// lookahead), against the true one; not while a clock change is still unseen.
LoadedRun run_loaded(LoadedHost host) {
  const double ticks_per_us = 1e-3 * (1.0 + 80e-6);
  const double h0 = 5e6, step_at = h0 + 19.05e6, reset_at = h0 + 27.05e6;
  const auto clock = [&](double h) {
    if (h >= reset_at) return 5.5 + ticks_per_us * (h - reset_at);
    return 1000.25 + ticks_per_us * (h - h0) - (h >= step_at ? 15.0 : 0.0);
  };
  std::vector<std::int64_t> sends;
  for (int i = 0; i < 8; ++i) sends.push_back(static_cast<std::int64_t>(h0) + i * 3'000);
  for (int i = 0; i < 300; ++i) sends.push_back(static_cast<std::int64_t>(h0) + 30'000 + i * 100'000);
  std::vector<SyncSample> samples;
  for (const std::int64_t sent : sends) {
    samples.push_back(host.exchange(clock, ticks_per_us, sent, (static_cast<double>(sent) - h0) * 1e-6));
    // Replies come back in the order they left.
    if (samples.size() > 1)
      samples.back().received_us = std::max(samples.back().received_us, samples[samples.size() - 2].received_us);
  }
  const auto first_after = [&](double t) {
    return static_cast<int>(
        std::find_if(sends.begin(), sends.end(), [&](std::int64_t s) { return static_cast<double>(s) > t; }) -
        sends.begin());
  };
  const int step_index = first_after(step_at), reset_index = first_after(reset_at);

  ClockSync c(ClockSync::Options{});
  LoadedRun out;
  std::size_t next = 0;
  for (std::int64_t h = samples[7].received_us; h <= samples.back().received_us; h += 10'000) {
    for (; next < samples.size() && samples[next].received_us <= h; ++next) {
      const Verdict v = c.add(samples[next]);
      const int index = static_cast<int>(next);
      out.held += v == Verdict::held ? 1 : 0;
      if (v == Verdict::step && out.step_seen_at == 0 && index >= step_index) out.step_seen_at = index - step_index + 1;
      if (v == Verdict::reset && out.reset_seen_at == 0 && index >= reset_index)
        out.reset_seen_at = index - reset_index + 1;
    }
    const double ahead = static_cast<double>(h) + 200'000.0;
    if ((ahead >= step_at && out.step_seen_at == 0) || (ahead >= reset_at && out.reset_seen_at == 0)) continue;
    out.worst_ticks =
        std::max(out.worst_ticks, std::fabs(*c.position(static_cast<std::int64_t>(ahead)) - clock(ahead)));
  }
  out.steps = c.steps();
  out.resets = c.resets();
  out.drift = c.drift();
  return out;
}

void expect_clock_kept(const LoadedRun& run) {
  // A tenth of a tick, a fifth of the rounding to a tick that every note has anyway. What an idle host
  // leaves: up to 0.02 tick from the legs' difference (half of up to 45 µs, averaged over the samples),
  // and before the drift is fitted (the first 2 s) 80 ppm over the weighted age of the samples plus the
  // 200 ms lookahead, about 0.05 tick more.
  EXPECT_LE(run.worst_ticks, 0.1);
  EXPECT_EQ(run.steps, 1u);
  EXPECT_EQ(run.resets, 1u);
  EXPECT_GE(run.step_seen_at, 1);
  EXPECT_LE(run.step_seen_at, 2);  // the first sample after the step is held, the second confirms it
  EXPECT_EQ(run.reset_seen_at, 1);
  // The fit of the last 3 s (since the restart) has σ ≈ 2 ppm from the legs' 30–75 µs spread.
  EXPECT_NEAR(run.drift * 1e6, 80.0, 8.0);
}

// Three seeds of a loaded host with only the named disturbances on; each run keeps the clock.
void expect_kept_for_seeds(std::initializer_list<unsigned> seeds, bool host_delays, bool overdue_ticks) {
  for (const unsigned seed : seeds) {
    SCOPED_TRACE(seed);
    LoadedHost host;
    host.rng.seed(seed);
    host.host_delays = host_delays;
    host.overdue_ticks = overdue_ticks;
    const LoadedRun run = run_loaded(host);
    expect_clock_kept(run);
    if (host_delays && overdue_ticks) {
      EXPECT_EQ(run.held, 1);  // only the first sample after the step waited
    }
  }
}

TEST(PlayerClockSync, BusyHostKeepsTheClockWithinATenthOfATick) { expect_kept_for_seeds({11u, 12u, 13u}, true, true); }

TEST(PlayerClockSync, DelaysOnEitherLegAloneDoNotMoveTheClock) { expect_kept_for_seeds({21u, 22u, 23u}, true, false); }

TEST(PlayerClockSync, OverdueTicksAloneAreNeverReadAsTheClock) { expect_kept_for_seeds({31u, 32u, 33u}, false, true); }

TEST(PlayerClockSync, OverdueReadingsAreSetAsideEvenWhenTheyAgree) {
  // Ten Syncs in a row meet the device 9 ticks behind with its tick interrupt overdue: the same reading
  // each time, and still no step. Only when no exact reading exists at all are they used.
  FakeDevice dev;
  ClockSync c(at_1khz());
  for (int i = 0; i < 8; ++i) c.add(dev.exchange(dev.h0 + i * 10'000, 50.0, 50.0));
  for (int i = 8; i < 18; ++i) {
    SyncSample s = dev.exchange(dev.h0 + i * 10'000, 5.0, 5.0);
    s.tick -= 9;
    s.subtick = ClockSync::kOverdueSubtick;
    s.received_us = s.sent_us + 10;
    EXPECT_EQ(c.add(s), Verdict::overdue) << i;
  }
  EXPECT_EQ(c.steps(), 0u);
  const double h = static_cast<double>(dev.h0) + 2e5;
  EXPECT_NEAR(*c.position(static_cast<std::int64_t>(h)), dev.position(h), 1e-3);
  EXPECT_NEAR(c.best_transit_us(), 100.0, 1.0);  // an overdue reply's transit means nothing

  ClockSync only_overdue(at_1khz());
  SyncSample s = dev.exchange(dev.h0, 50.0, 50.0);
  s.subtick = ClockSync::kOverdueSubtick;
  EXPECT_EQ(only_overdue.add(s), Verdict::overdue);
  ASSERT_TRUE(only_overdue.position(dev.h0).has_value());
  EXPECT_NEAR(*only_overdue.position(dev.h0), dev.position(static_cast<double>(dev.h0)), 1.0);
}

}  // namespace
