// Held notes (live input): Envelope::start_held and release_at against a double-precision reference
// written here from the contract in envelope.hpp: the preset's attack and decay as given, the sustain
// until the release, then from the level E(n_r) at the release tick down to r·E(n_r) over R (Eq. 10's
// form), the end fade over the last F ms, the note ending max(R, F) after the release (whole ticks).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "design_presets.hpp"
#include "shared/envelope/envelope.hpp"

namespace {

using hmp::envelope::Adsr;
using hmp::envelope::Envelope;
using hmp::envelope::Shape;

constexpr double kTolerance = 2e-5;  // of full scale (design §7)

struct Held {
  double a_ms, dc_ms, r_ms, s, r;  // the preset, s and r as fractions
  double peak, tick_hz, fade_ms;
  std::uint64_t release_tick;

  double ms(std::uint64_t n) const { return static_cast<double>(n) * 1000.0 / tick_hz; }
  // Before the release: attack, decay, sustain.
  double holding(double x) const {
    if (x < a_ms) return x * peak / a_ms;
    if (x < a_ms + dc_ms) return peak + (peak * s - peak) * (x - a_ms) / dc_ms;
    return peak * s;
  }
  std::uint64_t end_tick() const {
    const double ticks = std::ceil(std::max(r_ms, fade_ms) * tick_hz / 1000.0 - 1e-9);
    return release_tick + std::max<std::uint64_t>(1, static_cast<std::uint64_t>(ticks));
  }
  double at(std::uint64_t n) const {
    if (n < release_tick) return holding(ms(n));
    if (n >= end_tick()) return 0;
    const double level = holding(ms(release_tick));
    const double into = ms(n) - ms(release_tick);
    double e = level;
    if (r == 0) {
      e = into == 0 ? level : 0.0;
    } else if (r_ms > 0) {
      e = level * std::exp(std::log(r) * into / r_ms);
    }
    if (fade_ms > 0) e *= std::min(1.0, (ms(end_tick()) - ms(n)) / fade_ms);
    return e;
  }
};

// Plays the held note tick by tick from 0 (only the ticks near its phases when the release is far off)
// and compares every one with the reference.
void check(const Held& h) {
  SCOPED_TRACE("A=" + std::to_string(h.a_ms) + " Dc=" + std::to_string(h.dc_ms) + " R=" + std::to_string(h.r_ms) +
               " s=" + std::to_string(h.s) + " r=" + std::to_string(h.r) + " tick_hz=" + std::to_string(h.tick_hz) +
               " fade=" + std::to_string(h.fade_ms) + " release at " + std::to_string(h.release_tick));
  Envelope env;
  const Adsr adsr{static_cast<float>(h.a_ms), static_cast<float>(h.dc_ms), static_cast<float>(h.r_ms),
                  static_cast<float>(h.s),    static_cast<float>(h.r),     Shape::adsr};
  env.start_held(adsr, static_cast<float>(h.peak), static_cast<float>(h.tick_hz), static_cast<float>(h.fade_ms));
  ASSERT_TRUE(env.held());
  ASSERT_EQ(env.duration_ticks(), Envelope::kHeldTicks);
  const auto n_r = static_cast<std::uint32_t>(h.release_tick);
  const std::uint64_t phases_end = static_cast<std::uint64_t>(std::ceil((h.a_ms + h.dc_ms) * h.tick_hz / 1000)) + 4;
  for (std::uint64_t n = 0; n < std::min<std::uint64_t>(n_r, phases_end); ++n)
    ASSERT_NEAR(env.at(static_cast<std::uint32_t>(n)), h.at(n), kTolerance) << "holding, tick " << n;
  if (n_r > 0) {
    ASSERT_NEAR(env.at(n_r - 1), h.at(n_r - 1), kTolerance) << "the tick before the release";
  }
  const std::uint32_t end = env.release_at(n_r);
  EXPECT_FALSE(env.held());
  ASSERT_EQ(end, h.end_tick());
  EXPECT_EQ(env.duration_ticks(), end);
  EXPECT_EQ(env.release_at(n_r + 1), end) << "a second release changes nothing";
  for (std::uint64_t n = n_r; n < static_cast<std::uint64_t>(end) + 3; ++n)
    ASSERT_NEAR(env.at(static_cast<std::uint32_t>(n)), h.at(n), kTolerance) << "released, tick " << n;
}

TEST(EnvelopeHeld, TableOnePresetsReleasedInEveryPhase) {
  for (const auto& p : hmp::test::kDesignPresets) {
    for (const double tick_hz : {1000.0, 10000.0}) {
      for (const double fade : {0.0, 2.0}) {
        const double ticks_per_ms = tick_hz / 1000;
        // At the start, in the attack, in the decay, in the sustain, and after hours.
        for (const double x_ms : {0.0, p.a_ms / 2, p.a_ms + p.dc_ms / 3, p.a_ms + p.dc_ms + 250, 3.6e6}) {
          const auto n_r = static_cast<std::uint64_t>(std::floor(x_ms * ticks_per_ms));
          check({p.a_ms, p.dc_ms, p.r_ms, p.s_pct / 100, p.r_pct / 100, 0.8, tick_hz, fade, n_r});
        }
      }
    }
  }
}

TEST(EnvelopeHeld, ExtremesStayWithinTheContract) {
  // No release time and no fade: one tick at the level, then silence.
  check({5, 0, 0, 1, 0.01, 1, 1000, 0, 40});
  // A release to zero: the level on the release tick, 0 after.
  check({10, 20, 30, 0.5, 0, 1, 1000, 0, 100});
  // The fade longer than the release: the note lasts the fade.
  check({0, 0, 3, 1, 0.5, 1, 1000, 20, 7});
  // Held to the end of the tick counter (49.7 days at 1 kHz), a note ends by itself as a scheduled one of
  // kHeldTicks does, its release starting R before; a release there goes on from the level it has then.
  Envelope env, scheduled;
  const Adsr slow{1, 1, 1000, 0.5f, 0.1f, Shape::adsr};
  env.start_held(slow, 1, 1000, 2);
  scheduled.start(slow, 1, Envelope::kHeldTicks, 1000, 2);
  for (const std::uint32_t n : {Envelope::kHeldTicks - 2000, Envelope::kHeldTicks - 500, Envelope::kHeldTicks - 1})
    EXPECT_EQ(env.at(n), scheduled.at(n)) << n;
  const std::uint32_t late = Envelope::kHeldTicks - 10;
  const float level = env.at(late);
  EXPECT_EQ(env.release_at(late), Envelope::kHeldTicks) << "not past the counter's end";
  EXPECT_NEAR(env.at(late), level, kTolerance);
  EXPECT_EQ(env.at(Envelope::kHeldTicks), 0.0f);
  // Released at or past its end: nothing changes.
  env.start_held(Adsr{1, 1, 10, 0.5f, 0.1f, Shape::adsr}, 1, 1000, 2);
  EXPECT_EQ(env.release_at(Envelope::kHeldTicks), Envelope::kHeldTicks);
  EXPECT_TRUE(env.held());
}

TEST(EnvelopeHeld, ShapesSpanningTheNoteHoldThePeak) {
  for (const Shape shape : {Shape::triangle, Shape::damped}) {
    Envelope env;
    env.start_held(Adsr{0, 0, 0, 0.0f, 0.5f, shape}, 0.7f, 1000, 0);
    for (std::uint32_t n : {0u, 1u, 500u, 3000000u}) EXPECT_FLOAT_EQ(env.at(n), 0.7f) << static_cast<int>(shape);
    EXPECT_EQ(env.release_at(10), 11u) << "no release, no fade: one tick more";
  }
  // An invalid preset holds the peak as square does.
  Envelope env;
  env.start_held(Adsr{-1, 0, 0, 2.0f, 0.5f, Shape::adsr}, 0.25f, 1000, 0);
  EXPECT_FLOAT_EQ(env.at(123), 0.25f);
}

// A scheduled note is not held: release_at leaves it as it is.
TEST(EnvelopeHeld, AScheduledNoteIgnoresARelease) {
  Envelope env;
  env.start(Adsr{5, 0, 25, 1, 0.01f, Shape::adsr}, 1, 200, 1000, 2);
  EXPECT_FALSE(env.held());
  EXPECT_EQ(env.release_at(50), 200u);
  EXPECT_FLOAT_EQ(env.at(100), 1.0f);
}

}  // namespace
