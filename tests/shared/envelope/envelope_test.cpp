// Envelope (design §6) against an independent double-precision reference written here from docs/design.md text:
// a piecewise function of x in ms (Eq. 9–10 with Table 1's reading, short-note scaling, end fade).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <iterator>
#include <limits>
#include <random>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "design_presets.hpp"
#include "shared/envelope/envelope.hpp"

namespace {

using hmp::envelope::Adsr;
using hmp::envelope::Envelope;
using hmp::envelope::Preset;
using hmp::envelope::Shape;

constexpr double kTolerance = 2e-5;  // of full scale (design §7)

// One note as the test describes it: the preset and everything start() gets.
struct Note {
  Adsr adsr;
  float peak = 1;
  std::uint32_t ticks = 1;
  float tick_hz = 1000;
  float fade_ms = 0;
};

std::string describe(const Note& c) {
  std::ostringstream o;
  o.precision(9);
  o << "A=" << c.adsr.attack_ms << " Dc=" << c.adsr.decay_ms << " R=" << c.adsr.release_ms << " s=" << c.adsr.sustain
    << " r=" << c.adsr.final_ratio << " shape=" << static_cast<int>(c.adsr.shape) << " peak=" << c.peak
    << " N=" << c.ticks << " tick_hz=" << c.tick_hz << " fade=" << c.fade_ms;
  return o.str();
}

// design §6 read directly, in ms and double. Knows nothing of ticks except x = n·T.
class Reference {
 public:
  explicit Reference(const Note& c) : ms_per_tick_(1000.0 / static_cast<double>(c.tick_hz)) {
    const Adsr& a = c.adsr;
    d_ = std::max<std::uint32_t>(c.ticks, 1) * ms_per_tick_;
    peak_ = static_cast<double>(c.peak);
    double attack = static_cast<double>(a.attack_ms), decay = static_cast<double>(a.decay_ms),
           release = static_cast<double>(a.release_ms);
    // triangle: one decay over the whole note; damped: one release over the whole note, from the peak.
    if (a.shape != Shape::adsr) {
      attack = 0;
      decay = a.shape == Shape::triangle ? d_ : 0;
      release = a.shape == Shape::damped ? d_ : 0;
    }
    const bool short_note = attack + decay + release > d_;
    if (short_note) {
      const double k = d_ / (attack + decay + release);
      attack *= k;
      decay *= k;
      release *= k;
    }
    t1_ = attack;
    t2_ = attack + decay;
    t3_ = short_note ? t2_ : d_ - release;  // a short note has no sustain: t3 = t2 exactly, not to rounding
    level_ = a.shape == Shape::damped ? peak_ : peak_ * static_cast<double>(a.sustain);
    ratio_ = static_cast<double>(a.final_ratio);
    if (a.shape == Shape::damped) ratio_ = level_ > 0 ? std::min(1.0, ratio_ / level_) : 1.0;
    fade_ = static_cast<double>(c.fade_ms);
  }

  double at_ms(double x) const {
    if (x >= d_) return 0;
    double e;
    if (x < t1_) {
      e = x * peak_ / t1_;
    } else if (x < t2_) {
      const double m = (level_ - peak_) / (t2_ - t1_);  // Eq. 9
      e = m * (x - t1_) + peak_;                        // Eq. 10, second line
    } else if (x < t3_) {
      e = level_;
    } else if (ratio_ == 0) {
      e = x == t3_ ? level_ : 0.0;
    } else {
      e = level_ * std::exp(std::log(ratio_) * (x - t3_) / (d_ - t3_));
    }
    if (fade_ > 0) e *= std::min(1.0, (d_ - x) / fade_);
    return e;
  }
  double x_of(std::uint64_t n) const { return static_cast<double>(n) * ms_per_tick_; }

  // Distance of a float sample to the reference at tick n. Where x sits on a boundary to within rounding
  // of its ms↔tick conversion, either side's value is right (docs/design.md fixes boundaries only in real numbers).
  double error(std::uint64_t n, float v) const {
    const double x = x_of(n);
    const double eps = 1e-11 * std::max(1.0, x);
    double best = std::abs(static_cast<double>(v) - at_ms(x));
    for (double xs : {x - eps, x + eps}) {
      if (xs >= 0) best = std::min(best, std::abs(static_cast<double>(v) - at_ms(xs)));
    }
    return best;
  }

  // The steepest the envelope can change over one tick where it is continuous.
  double max_step() const {
    double slope = 0;  // per ms
    if (t1_ > 0) slope += peak_ / t1_;
    if (t2_ > t1_) slope += (peak_ - level_) / (t2_ - t1_);
    if (d_ > t3_ && ratio_ > 0) slope += level_ * std::abs(std::log(ratio_)) / (d_ - t3_);
    if (fade_ > 0) slope += peak_ / fade_;
    return slope * ms_per_tick_;
  }
  // The places where design §6 allows a step: a zero-length decay below the peak, and r = 0 right after t3.
  bool step_between(std::uint64_t n) const {
    const double lo = x_of(n), hi = x_of(n + 1);
    const double eps = 1e-9 * std::max(1.0, hi);
    auto inside = [&](double s) { return s >= lo - eps && s <= hi + eps; };
    if (t2_ == t1_ && level_ < peak_ && inside(t1_)) return true;
    if (ratio_ == 0 && t3_ < d_ && inside(t3_)) return true;
    return false;
  }

  std::vector<double> boundaries_ms() const { return {t1_, t2_, t3_, d_ - fade_, d_}; }
  double ms_per_tick() const { return ms_per_tick_; }

 private:
  double ms_per_tick_;
  double d_ = 0, peak_ = 0, t1_ = 0, t2_ = 0, t3_ = 0, level_ = 0, ratio_ = 1, fade_ = 0;
};

struct Stats {
  double max_error = 0;
  std::uint64_t samples = 0;
  int failures = 0;
};

// Ticks to compare: all of a short note; for a long one, its start and end, every phase boundary and
// random ticks, each with its successor so that steps between neighbours can be checked.
std::vector<std::uint64_t> ticks_to_check(const Note& c, const Reference& ref, std::uint32_t exhaustive_up_to,
                                          std::mt19937_64& rng) {
  const std::uint64_t n = std::max<std::uint32_t>(c.ticks, 1);
  std::vector<std::uint64_t> out;
  if (n <= exhaustive_up_to) {
    for (std::uint64_t i = 0; i <= n + 1; ++i) out.push_back(i);
    return out;
  }
  auto window = [&](double centre, std::uint64_t half) {
    const double lo = std::max(0.0, centre - static_cast<double>(half));
    const double hi = std::min(static_cast<double>(n + 1), centre + static_cast<double>(half));
    for (auto i = static_cast<std::uint64_t>(lo); static_cast<double>(i) <= hi; ++i) out.push_back(i);
  };
  window(0, 2000);
  window(static_cast<double>(n), 2000);
  for (double b : ref.boundaries_ms()) window(b / ref.ms_per_tick(), 4);
  std::uniform_int_distribution<std::uint64_t> any(0, n - 1);
  for (int i = 0; i < 2000; ++i) {
    const std::uint64_t t = any(rng);
    out.push_back(t);
    out.push_back(t + 1);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

void check_note(const Note& c, Stats& stats, std::mt19937_64& rng, std::uint32_t exhaustive_up_to = 200000) {
  Envelope e;
  e.start(c.adsr, c.peak, c.ticks, c.tick_hz, c.fade_ms);
  const Reference ref(c);
  const auto ticks = ticks_to_check(c, ref, exhaustive_up_to, rng);
  const double step_limit = ref.max_step() + 2 * kTolerance;
  auto fail = [&](const std::string& what) {
    if (++stats.failures <= 5) ADD_FAILURE() << what << " for " << describe(c);
  };
  float previous = 0;
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    const std::uint64_t n = ticks[i];
    const float v = e.at(static_cast<std::uint32_t>(n));
    ++stats.samples;
    if (!std::isfinite(v) || v < 0 || v > c.peak) {
      fail("sample " + std::to_string(n) + " = " + std::to_string(v) + " outside [0, peak]");
      continue;
    }
    const double err = ref.error(n, v);
    stats.max_error = std::max(stats.max_error, err);
    if (err > kTolerance) {
      fail("sample " + std::to_string(n) + ": " + std::to_string(v) + " vs reference " +
           std::to_string(ref.at_ms(ref.x_of(n))) + " (error " + std::to_string(err) + ")");
    }
    const bool neighbours_inside = i > 0 && ticks[i - 1] + 1 == n && n < std::max<std::uint32_t>(c.ticks, 1);
    if (neighbours_inside && !ref.step_between(n - 1) &&
        std::abs(static_cast<double>(v) - static_cast<double>(previous)) > step_limit) {
      fail("step between ticks " + std::to_string(n - 1) + " and " + std::to_string(n) + ": " +
           std::to_string(previous) + " → " + std::to_string(v) + " (limit " + std::to_string(step_limit) + ")");
    }
    previous = v;
  }
}

Adsr preset(Preset p) { return hmp::envelope::builtin(p); }

constexpr Preset kAllPresets[] = {Preset::organ,   Preset::flute,    Preset::harpsichord, Preset::guitar,
                                  Preset::trumpet, Preset::violin,   Preset::cello,       Preset::contrabass,
                                  Preset::square,  Preset::triangle, Preset::legacy2013};

// ---------------------------------------------------------------------------------------------------------

TEST(EnvelopePresets, MatchSpecTable) {
  // Table 1's instruments (square's stored release is checked with the other shapes below).
  const auto rows = std::span(hmp::test::kDesignPresets).first(8);
  for (const hmp::test::DesignPreset& row : rows) {
    Preset p{};
    ASSERT_TRUE(hmp::envelope::find_builtin(row.name, p)) << row.name;
    const Adsr& a = hmp::envelope::builtin(p);
    EXPECT_EQ(a.shape, Shape::adsr) << row.name;
    EXPECT_FLOAT_EQ(a.attack_ms, static_cast<float>(row.a_ms)) << row.name;
    EXPECT_FLOAT_EQ(a.decay_ms, static_cast<float>(row.dc_ms)) << row.name;
    EXPECT_FLOAT_EQ(a.release_ms, static_cast<float>(row.r_ms)) << row.name;
    EXPECT_FLOAT_EQ(a.sustain, static_cast<float>(row.s_pct / 100)) << row.name;
    EXPECT_FLOAT_EQ(a.final_ratio, static_cast<float>(row.r_pct / 100)) << row.name;
  }
  const Adsr& legacy = preset(Preset::legacy2013);
  EXPECT_EQ(legacy.shape, Shape::damped);
  EXPECT_FLOAT_EQ(legacy.final_ratio, 0.05f);
  EXPECT_EQ(preset(Preset::triangle).shape, Shape::triangle);
  EXPECT_EQ(preset(Preset::triangle).sustain, 0.0f);
  for (Preset p : kAllPresets) EXPECT_TRUE(hmp::envelope::valid(preset(p))) << hmp::envelope::name(p);
}

TEST(EnvelopePresets, NamesRoundTripCaseInsensitively) {
  const char* expected[] = {"organ", "flute",      "harpsichord", "guitar",   "trumpet",   "violin",
                            "cello", "contrabass", "square",      "triangle", "legacy2013"};
  ASSERT_EQ(std::size(expected), std::size_t{hmp::envelope::kBuiltinCount});
  for (std::uint8_t i = 0; i < hmp::envelope::kBuiltinCount; ++i) {
    const auto p = static_cast<Preset>(i);
    EXPECT_STREQ(hmp::envelope::name(p), expected[i]);
    std::string upper = expected[i];
    for (char& ch : upper) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    Preset found{};
    ASSERT_TRUE(hmp::envelope::find_builtin(upper.c_str(), found)) << upper;
    EXPECT_EQ(found, p);
  }
  Preset found = Preset::organ;
  EXPECT_TRUE(hmp::envelope::find_builtin("ViOlIn", found));
  EXPECT_EQ(found, Preset::violin);
  for (const char* bad : {"", "violins", "violi", "analogue", "auto", " organ"}) {
    EXPECT_FALSE(hmp::envelope::find_builtin(bad, found)) << bad;
  }
  EXPECT_FALSE(hmp::envelope::find_builtin(nullptr, found));
}

TEST(EnvelopePresets, EveryNameLeadsBackToItsPreset) {
  // name → preset → name for every built-in, whatever its place in the table.
  for (std::uint8_t i = 0; i < hmp::envelope::kBuiltinCount; ++i) {
    const std::string name = hmp::envelope::name(static_cast<Preset>(i));
    Preset found{};
    ASSERT_TRUE(hmp::envelope::find_builtin(name.c_str(), found)) << name;
    EXPECT_EQ(static_cast<unsigned>(found), unsigned{i}) << name;
    EXPECT_EQ(hmp::envelope::name(found), name);
  }
  EXPECT_STREQ(hmp::envelope::name(Preset::count), "unknown");
}

// Hand-computed points of Table 1's violin at 1 kHz (A 66, Dc 376, R 225, s 57.14 %, r 1 %), one second.
TEST(EnvelopeShape, ViolinByHand) {
  Envelope e;
  e.start(preset(Preset::violin), 0.5f, 1000, 1000.0f, 0.0f);
  EXPECT_NEAR(e.at(0), 0.0, 1e-7);
  EXPECT_NEAR(e.at(33), 0.25, 1e-6);                                           // half-way up the attack
  EXPECT_NEAR(e.at(66), 0.5, 1e-6);                                            // peak
  EXPECT_NEAR(e.at(66 + 188), 0.5 * (1 + 0.5714) / 2, 1e-6);                   // half-way down the decay
  EXPECT_NEAR(e.at(500), 0.5 * 0.5714, 1e-6);                                  // sustain
  EXPECT_NEAR(e.at(775), 0.5 * 0.5714, 1e-6);                                  // release starts at D − R
  EXPECT_NEAR(e.at(887), 0.5 * 0.5714 * std::pow(0.01, 112.0 / 225.0), 1e-6);  // 112 ms into the release
  EXPECT_NEAR(e.at(999), 0.5 * 0.5714 * std::pow(0.01, 224.0 / 225.0), 1e-6);
  EXPECT_EQ(e.at(1000), 0.0f);
  EXPECT_EQ(e.at(std::numeric_limits<std::uint32_t>::max()), 0.0f);
}

TEST(EnvelopeShape, SquareTriangleAndLegacyByHand) {
  Envelope square, triangle, legacy;
  square.start(preset(Preset::square), 0.8f, 100, 1000.0f, 0.0f);
  triangle.start(preset(Preset::triangle), 0.8f, 100, 1000.0f, 0.0f);
  legacy.start(preset(Preset::legacy2013), 0.8f, 100, 1000.0f, 0.0f);
  for (std::uint32_t n = 0; n < 100; ++n) {
    EXPECT_FLOAT_EQ(square.at(n), 0.8f);
    EXPECT_NEAR(triangle.at(n), 0.8 * (1 - n / 100.0), 1e-6);
    // 2013 Eq. 6: decay = ln(force_min / keyamp) / duration, from the peak to 0.05 at D.
    EXPECT_NEAR(legacy.at(n), 0.8 * std::exp(std::log(0.05 / 0.8) * n / 100.0), 1e-6);
  }
  // A peak below the end level: nothing to damp.
  legacy.start(preset(Preset::legacy2013), 0.02f, 100, 1000.0f, 0.0f);
  EXPECT_FLOAT_EQ(legacy.at(99), 0.02f);
}

TEST(EnvelopeShape, ZeroAndOneTickNotes) {
  for (Preset p : kAllPresets) {
    Envelope e;
    e.start(preset(p), 1.0f, 0, 1000.0f, 2.0f);
    EXPECT_EQ(e.duration_ticks(), 1u) << hmp::envelope::name(p);
    EXPECT_TRUE(std::isfinite(e.at(0)));
    EXPECT_EQ(e.at(1), 0.0f);
  }
}

TEST(EnvelopeShape, ReleaseToZeroIsAStepRightAfterT3) {
  Adsr a;
  a.release_ms = 10;
  a.sustain = 0.5f;
  a.final_ratio = 0;
  Envelope e;
  e.start(a, 1.0f, 100, 1000.0f, 0.0f);
  EXPECT_FLOAT_EQ(e.at(89), 0.5f);
  EXPECT_FLOAT_EQ(e.at(90), 0.5f);  // x = t3: exp(log(0)·0) read as 1
  EXPECT_EQ(e.at(91), 0.0f);
  EXPECT_EQ(e.at(99), 0.0f);
}

// A short note with no attack or decay is all release, starting at x = 0 = t3 exactly, whatever rounding
// the scale factor D/(A + Dc + R) brings: with r = 0 the first sample is still S.
TEST(EnvelopeShape, ShortNoteOfOnlyReleaseStartsAtSustain) {
  Adsr a;
  a.sustain = 0.5f;
  a.final_ratio = 0;
  for (int release = 100; release <= 1000; ++release) {
    a.release_ms = static_cast<float>(release);
    for (std::uint32_t ticks = 1; ticks < 100; ++ticks) {
      Envelope e;
      e.start(a, 1.0f, ticks, 1000.0f, 0.0f);
      ASSERT_FLOAT_EQ(e.at(0), 0.5f) << "R " << release << " N " << ticks;
      if (ticks > 1) {
        ASSERT_EQ(e.at(1), 0.0f) << "R " << release << " N " << ticks;
      }
    }
  }
}

TEST(EnvelopeShape, EndFadeRampsTheLastMilliseconds) {
  Envelope e;
  e.start(preset(Preset::square), 1.0f, 100, 1000.0f, 4.0f);
  EXPECT_FLOAT_EQ(e.at(95), 1.0f);
  EXPECT_FLOAT_EQ(e.at(96), 1.0f);  // (D − x)/F = 4/4
  EXPECT_FLOAT_EQ(e.at(97), 0.75f);
  EXPECT_FLOAT_EQ(e.at(99), 0.25f);
}

// Every preset at the durations and tick rates of the brief, every tick compared.
TEST(EnvelopeAccuracy, PresetsAgainstReference) {
  std::mt19937_64 rng(1);
  Stats stats;
  for (Preset p : kAllPresets) {
    for (std::uint32_t ticks : {1u, 2u, 10u, 50u, 137u, 1000u, 60000u}) {
      for (float hz : {1000.0f, 10000.0f}) {
        for (float fade : {0.0f, 2.0f}) {
          for (float peak : {1.0f, 0.3f}) check_note({preset(p), peak, ticks, hz, fade}, stats, rng);
        }
      }
    }
  }
  std::cout << "presets: max |float - double| = " << stats.max_error << " over " << stats.samples << " samples\n";
  EXPECT_LE(stats.max_error, kTolerance);
}

// The 10-minute note of design §7, at 1 kHz and 10 kHz, every tick.
TEST(EnvelopeAccuracy, TenMinuteNotes) {
  std::mt19937_64 rng(2);
  Stats stats;
  for (Preset p : kAllPresets) {
    for (float hz : {1000.0f, 10000.0f}) {
      const auto ticks = static_cast<std::uint32_t>(600.0f * hz);
      check_note({preset(p), 1.0f, ticks, hz, 2.0f}, stats, rng, 10'000'000);
    }
  }
  std::cout << "10-minute notes: max |float - double| = " << stats.max_error << " over " << stats.samples
            << " samples\n";
  EXPECT_LE(stats.max_error, kTolerance);
}

// Random presets, including every degenerate value docs/design.md names, and durations from 0 to hours.
TEST(EnvelopeAccuracy, RandomPresetsAgainstReference) {
  std::mt19937_64 rng(20240611);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto log_uniform = [&](double lo, double hi) { return lo * std::pow(hi / lo, unit(rng)); };
  auto duration_ms = [&] {
    const double u = unit(rng);
    if (u < 0.25) return 0.0;
    if (u < 0.35) return log_uniform(1e-4, 1.0);
    if (u < 0.95) return log_uniform(1.0, 1e6);
    return log_uniform(1e6, 1e7);
  };
  Stats stats;
  constexpr int kCases = 2000;
  for (int i = 0; i < kCases; ++i) {
    Note c;
    c.adsr.attack_ms = static_cast<float>(duration_ms());
    c.adsr.decay_ms = static_cast<float>(duration_ms());
    c.adsr.release_ms = static_cast<float>(duration_ms());
    const double s = unit(rng);
    c.adsr.sustain = s < 0.2 ? 0.0f : (s < 0.4 ? 1.0f : static_cast<float>(unit(rng)));
    const double r = unit(rng);
    c.adsr.final_ratio = r < 0.2 ? 0.0f : (r < 0.3 ? 1.0f : static_cast<float>(log_uniform(1e-6, 1.0)));
    const double shape = unit(rng);
    c.adsr.shape = shape < 0.7 ? Shape::adsr : (shape < 0.85 ? Shape::triangle : Shape::damped);
    c.peak = unit(rng) < 0.2 ? 1.0f : static_cast<float>(std::max(1e-3, unit(rng)));
    const double rate = unit(rng);
    c.tick_hz = rate < 0.45 ? 1000.0f : (rate < 0.9 ? 10000.0f : static_cast<float>(100 + 19900 * unit(rng)));
    c.fade_ms = unit(rng) < 0.4 ? 0.0f : static_cast<float>(log_uniform(0.01, 1e4));
    // Note lengths: 0–1 ms, up to a minute, or hours (up to ~1e8 ticks).
    const double len = unit(rng);
    const double note_ms = len < 0.2 ? unit(rng) : (len < 0.8 ? log_uniform(1, 6e4) : log_uniform(6e4, 1e7));
    const double ticks = std::round(note_ms * static_cast<double>(c.tick_hz) / 1000);
    c.ticks = static_cast<std::uint32_t>(std::min(1e8, ticks));
    // Integer-millisecond phases at 1 kHz put boundaries exactly on ticks: keep some of those too.
    if (i % 10 == 0) {
      c.adsr.attack_ms = std::round(c.adsr.attack_ms);
      c.adsr.decay_ms = std::round(c.adsr.decay_ms);
      c.adsr.release_ms = std::round(c.adsr.release_ms);
    }
    ASSERT_TRUE(hmp::envelope::valid(c.adsr)) << describe(c);
    check_note(c, stats, rng, 20000);
  }
  std::cout << "random presets: max |float - double| = " << stats.max_error << " over " << stats.samples
            << " samples in " << kCases << " notes\n";
  EXPECT_LE(stats.max_error, kTolerance);
}

TEST(EnvelopeValidity, InvalidPresetsFallBackToSquare) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<Adsr> bad;
  auto with = [&](auto change) {
    Adsr a = preset(Preset::violin);
    change(a);
    bad.push_back(a);
  };
  with([&](Adsr& a) { a.attack_ms = nan; });
  with([&](Adsr& a) { a.decay_ms = -1; });
  with([&](Adsr& a) { a.release_ms = inf; });
  with([&](Adsr& a) { a.release_ms = 1.5e7f; });
  with([&](Adsr& a) { a.sustain = 1.01f; });
  with([&](Adsr& a) { a.sustain = nan; });
  with([&](Adsr& a) { a.final_ratio = -0.1f; });
  with([&](Adsr& a) { a.final_ratio = 2; });
  with([&](Adsr& a) { a.shape = static_cast<Shape>(7); });
  for (const Adsr& a : bad) {
    EXPECT_FALSE(hmp::envelope::valid(a));
    for (float fade : {0.0f, 3.0f}) {
      Envelope e, square;
      e.start(a, 0.7f, 500, 1000.0f, fade);
      square.start(preset(Preset::square), 0.7f, 500, 1000.0f, fade);
      for (std::uint32_t n = 0; n <= 501; ++n) ASSERT_EQ(e.at(n), square.at(n)) << n;
      EXPECT_FLOAT_EQ(e.at(250), 0.7f);
    }
  }
  // Edges of the valid range are valid.
  Adsr edge;
  edge.attack_ms = 1e7f;
  edge.sustain = 0;
  edge.final_ratio = 1;
  EXPECT_TRUE(hmp::envelope::valid(edge));
}

TEST(EnvelopeValidity, BadArgumentsStayFiniteAndInRange) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (Preset p : kAllPresets) {
    for (float peak : {nan, -1.0f, 0.0f, 2.0f, inf}) {
      for (float hz : {nan, 0.0f, -1000.0f, inf, 1000.0f}) {
        for (float fade : {nan, -2.0f, inf, 1e30f, 0.0f}) {
          Envelope e;
          e.start(preset(p), peak, 300, hz, fade);
          for (std::uint32_t n = 0; n <= 300; ++n) {
            const float v = e.at(n);
            ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f)
                << hmp::envelope::name(p) << " peak " << peak << " hz " << hz << " fade " << fade << " n " << n;
          }
        }
      }
    }
  }
  // Without a time base the preset cannot be placed: square, peak for the whole note.
  Envelope e;
  e.start(preset(Preset::violin), 0.5f, 10, nan, 2.0f);
  EXPECT_FLOAT_EQ(e.at(9), 0.5f);
}

// Phases far shorter than a tick must not turn into inf·0 = NaN.
TEST(EnvelopeValidity, TinyPhasesStayFinite) {
  const float tiny = std::numeric_limits<float>::denorm_min();
  for (Shape shape : {Shape::adsr, Shape::triangle, Shape::damped}) {
    Adsr a;
    a.attack_ms = tiny;
    a.decay_ms = tiny;
    a.release_ms = tiny;
    a.sustain = 0.3f;
    a.final_ratio = 0.5f;
    a.shape = shape;
    for (std::uint32_t ticks : {1u, 2u, 5u}) {
      Envelope e;
      e.start(a, 1.0f, ticks, 10000.0f, tiny);
      for (std::uint32_t n = 0; n <= ticks; ++n) {
        const float v = e.at(n);
        EXPECT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f) << static_cast<int>(shape) << " " << n;
      }
    }
  }
}

}  // namespace
