// PlaybackClock: nominal behaviour (start, pause, resume, inverse), and tracking of a sound card whose
// clock drifts against the host's, from jittery buffer reports, checked against the exact drifting
// line the test generated.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <random>

#include "host/audio/playback_clock.hpp"

namespace {

using hmp::audio::PlaybackClock;
using Clock = std::chrono::steady_clock;
using std::chrono::microseconds;

const Clock::time_point t0 = Clock::time_point{} + std::chrono::hours(1);

TEST(AudioClock, RunsAtNominalSpeedPausesAndInverts) {
  PlaybackClock c;
  EXPECT_FALSE(c.running());
  EXPECT_EQ(c.song_us(t0), 0);
  c.start(2'000'000, t0);
  EXPECT_EQ(c.song_us(t0), 2'000'000);
  EXPECT_EQ(c.song_us(t0 + microseconds(1'500'000)), 3'500'000);
  EXPECT_EQ(c.song_us(t0 - microseconds(20'000)), 1'980'000);  // before the first sample is heard
  EXPECT_EQ(c.heard_at(2'500'000), t0 + microseconds(500'000));
  c.pause(t0 + microseconds(1'000'000));
  EXPECT_FALSE(c.running());
  EXPECT_EQ(c.song_us(t0 + microseconds(9'000'000)), 3'000'000);
  c.set_paused_position(10'000'000);
  EXPECT_EQ(c.song_us(t0), 10'000'000);
  c.observe(5, t0);  // ignored while paused
  EXPECT_EQ(c.song_us(t0), 10'000'000);
}

// A card playing `ppm` fast: song position p is heard at host time t0 + p / (1 + ppm·1e-6). The audio
// callback reports every 256 frames at 48 kHz with ±jitter of scheduling noise.
double tracking_error_us(double ppm, double jitter_us, double seconds, unsigned seed) {
  PlaybackClock c;
  c.start(0, t0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-jitter_us, jitter_us);
  const double speed = 1.0 + ppm * 1e-6;
  const double period_us = 256.0 / 48000.0 * 1e6;
  double worst = 0;
  for (double p = 0; p < seconds * 1e6; p += period_us) {
    const double heard = p / speed;
    c.observe(static_cast<std::int64_t>(p), t0 + microseconds(static_cast<std::int64_t>(heard + noise(rng))));
    if (p > 2e6) {  // after two seconds: compare the reading with the truth half a period later
      const double t = heard + period_us / 2;
      const double truth = t * speed;
      worst = std::max(
          worst, std::fabs(static_cast<double>(c.song_us(t0 + microseconds(static_cast<std::int64_t>(t)))) - truth));
    }
  }
  return worst;
}

TEST(AudioClock, FollowsADriftingCardThroughJitter) {
  // Without tracking, 300 ppm over 20 s is 6 ms of skew; the fit must stay within 0.5 ms.
  EXPECT_LT(tracking_error_us(300, 1000, 20, 1), 500.0);
  EXPECT_LT(tracking_error_us(-300, 1000, 20, 2), 500.0);
  EXPECT_LT(tracking_error_us(0, 0, 5, 3), 2.0);
}

TEST(AudioClock, SpeedEstimateIsClampedToPlausibleCards) {
  PlaybackClock c;
  c.start(0, t0);
  // Reports claiming the song runs 1 % fast (impossible for a sound card).
  for (int i = 0; i < 200; ++i) c.observe(i * 10'100, t0 + microseconds(i * 10'000));
  EXPECT_LE(c.speed(), 1.0 + PlaybackClock::kMaxSpeedError + 1e-12);
}

TEST(AudioClock, AnUnderrunRestartsTheLine) {
  PlaybackClock c;
  c.start(0, t0);
  for (int i = 0; i < 100; ++i) c.observe(i * 5'000, t0 + microseconds(i * 5'000));
  // The driver stalled 80 ms: from now on the song is heard 80 ms later than the line says.
  const std::int64_t stall = 80'000;
  for (int i = 100; i < 110; ++i) c.observe(i * 5'000, t0 + microseconds(i * 5'000 + stall));
  EXPECT_EQ(c.restarts(), 1u);
  const auto t = t0 + microseconds(110 * 5'000 + stall);
  EXPECT_NEAR(static_cast<double>(c.song_us(t)), 110 * 5'000.0, 100.0);
}

// A card heard exactly on the nominal line, reported by callbacks of which some run late (the host
// was busy: up to `late_us`, less than the buffer). Largest reading error over the run.
double error_with_late_callbacks(double late_us, double fraction, unsigned seed, std::uint64_t& restarts) {
  PlaybackClock c;
  c.set_buffer_us(21'333);  // 4 × 256 frames at 48 kHz
  c.start(0, t0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const double period_us = 256.0 / 48000.0 * 1e6;
  double worst = 0;
  for (double p = 0; p < 20e6; p += period_us) {
    const double lateness = u(rng) < fraction ? late_us * u(rng) : 30 * u(rng);
    c.observe(static_cast<std::int64_t>(p), t0 + microseconds(static_cast<std::int64_t>(p + lateness)));
    if (p > 1e6) {
      const double t = p + period_us / 2;
      worst = std::max(worst,
                       std::fabs(static_cast<double>(c.song_us(t0 + microseconds(static_cast<std::int64_t>(t)))) - t));
    }
  }
  restarts = c.restarts();
  return worst;
}

TEST(AudioClock, LateCallbacksWithinTheBufferDoNotMoveTheClock) {
  // 5 % of the callbacks up to 18 ms late (a busy host), the buffer holding 21 ms: the card never ran
  // dry, so what is heard stays on the line, and so must the clock.
  std::uint64_t restarts = 0;
  EXPECT_LT(error_with_late_callbacks(18'000, 0.05, 4, restarts), 100.0);
  EXPECT_EQ(restarts, 0u);
  // A third of them late still does not move it by more than a quarter of the 1 ms skew budget (the
  // ones less than 2 ms late are taken as jitter and pull the line a little).
  EXPECT_LT(error_with_late_callbacks(18'000, 0.33, 5, restarts), 250.0);
  EXPECT_EQ(restarts, 0u);
}

TEST(AudioClock, AShiftSmallerThanTheBufferIsFollowedAfterARunOfReports) {
  PlaybackClock c;
  c.set_buffer_us(21'333);
  c.start(0, t0);
  for (int i = 0; i < 200; ++i) c.observe(i * 5'000, t0 + microseconds(i * 5'000));
  // From here every report says 6 ms later (a driver that re-started its stream): one report is not
  // believed, a run of them is.
  const std::int64_t shift = 6'000;
  c.observe(200 * 5'000, t0 + microseconds(200 * 5'000 + shift));
  EXPECT_EQ(c.restarts(), 0u);
  EXPECT_NEAR(static_cast<double>(c.song_us(t0 + microseconds(200 * 5'000))), 200 * 5'000.0, 50.0);
  for (int i = 201; i < 201 + static_cast<int>(PlaybackClock::kMinFit) + 40; ++i) {
    c.observe(i * 5'000, t0 + microseconds(i * 5'000 + shift));
  }
  EXPECT_EQ(c.restarts(), 1u);
  const auto t = t0 + microseconds(300 * 5'000 + shift);
  EXPECT_NEAR(static_cast<double>(c.song_us(t)), 300 * 5'000.0, 100.0);
}

}  // namespace
