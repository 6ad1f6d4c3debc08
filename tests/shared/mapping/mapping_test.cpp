// Pitch → haptic frequency and amplitude (design §5), checked against formulas written here from docs/design.md
// and the papers, plus brute-force checks of the key set.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "shared/mapping/mapping.hpp"

namespace {

using hmp::mapping::Haptic;
using hmp::mapping::KeySet;
using hmp::mapping::Mapper;
using hmp::mapping::Mode;
using hmp::mapping::Ranges;

constexpr double kEps = 1e-9;

KeySet make_keys(const std::vector<int>& keys) {
  KeySet set;
  for (int k : keys) set.add(static_cast<std::uint8_t>(k));
  return set;
}

// A random set of 1–40 distinct keys somewhere in 0–127.
std::vector<int> random_keys(std::mt19937_64& rng) {
  std::uniform_int_distribution<int> size(1, 40), key(0, 127);
  std::vector<bool> used(128, false);
  const int want = size(rng);
  for (int i = 0; i < want; ++i) used[static_cast<std::size_t>(key(rng))] = true;
  std::vector<int> keys;
  for (int k = 0; k < 128; ++k) {
    if (used[static_cast<std::size_t>(k)]) keys.push_back(k);
  }
  return keys;
}

double db_to_linear_ref(double db, double max_db) { return std::pow(10.0, (db - max_db) / 20.0); }

TEST(KeySet, AgreesWithBruteForce) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 500; ++trial) {
    const std::vector<int> keys = random_keys(rng);
    const KeySet set = make_keys(keys);
    EXPECT_EQ(set.count(), static_cast<int>(keys.size()));
    EXPECT_EQ(set.min(), keys.front());
    EXPECT_EQ(set.max(), keys.back());
    for (int k = 0; k < 128; ++k) {
      int rank = -1;
      for (std::size_t i = 0; i < keys.size(); ++i) {
        if (keys[i] == k) rank = static_cast<int>(i);
      }
      const auto key = static_cast<std::uint8_t>(k);
      EXPECT_EQ(set.contains(key), rank >= 0) << k;
      EXPECT_EQ(set.rank(key), rank) << k;
      int below = 0;
      for (int other : keys) below += other < k ? 1 : 0;
      EXPECT_EQ(set.count_below(key), below) << k;
    }
  }
}

TEST(KeySet, EmptyEdgesAndOutOfRangeKeys) {
  KeySet set;
  EXPECT_EQ(set.count(), 0);
  EXPECT_EQ(set.min(), -1);
  EXPECT_EQ(set.max(), -1);
  EXPECT_EQ(set.rank(60), -1);
  set.add(200);  // not a MIDI key
  set.add(128);
  EXPECT_EQ(set.count(), 0);
  EXPECT_FALSE(set.contains(200));
  for (int k : {0, 63, 64, 127}) set.add(static_cast<std::uint8_t>(k));
  set.add(64);  // twice: still one distinct key
  EXPECT_EQ(set.count(), 4);
  EXPECT_EQ(set.min(), 0);
  EXPECT_EQ(set.max(), 127);
  EXPECT_EQ(set.rank(63), 1);
  EXPECT_EQ(set.rank(64), 2);
  EXPECT_EQ(set.rank(127), 3);
}

TEST(DbToLinear, FullScaleAndPaperFloor) {
  EXPECT_NEAR(hmp::mapping::db_to_linear(7.5, 30), 0.0750, 1e-4);
  EXPECT_DOUBLE_EQ(hmp::mapping::db_to_linear(30, 30), 1.0);
  EXPECT_NEAR(hmp::mapping::db_to_linear(24, 30), 0.5012, 1e-4);  // −6 dB ≈ half
  EXPECT_NEAR(hmp::mapping::db_to_linear(10, 30), 0.1, 1e-12);
}

// Eq. 5–7 as printed are linear interpolation in k: f = f_min + Δf (k − k_min)/Δk, the same for a_dB.
TEST(PaperMode, IsLinearInterpolationInKey) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> fr(1, 500), ar(-20, 40);
  for (int trial = 0; trial < 500; ++trial) {
    std::vector<int> keys = random_keys(rng);
    if (keys.size() < 2) continue;
    Ranges r;
    r.f_min_hz = fr(rng);
    r.f_max_hz = r.f_min_hz + fr(rng);
    r.a_min_db = ar(rng);
    r.a_max_db = r.a_min_db + fr(rng) / 10;
    const Mapper m(Mode::paper, r, make_keys(keys));
    const double k_min = keys.front(), dk = keys.back() - keys.front();
    // Every key of the range, in the set or not (a key between two set keys is interpolated too).
    for (int k = keys.front(); k <= keys.back(); ++k) {
      const Haptic h = m.map(static_cast<std::uint8_t>(k));
      const double u = (k - k_min) / dk;
      EXPECT_NEAR(h.freq_hz, r.f_min_hz + (r.f_max_hz - r.f_min_hz) * u, kEps);
      const double a_db = r.a_min_db + (r.a_max_db - r.a_min_db) * u;
      EXPECT_NEAR(h.amplitude, db_to_linear_ref(a_db, r.a_max_db), kEps);
    }
  }
}

TEST(PaperMode, EndpointsAreTheRangeEnds) {
  const Ranges r;  // 50–250 Hz, 7.5–30 dB
  const Mapper m(Mode::paper, r, make_keys({40, 45, 52, 76}));
  EXPECT_NEAR(m.map(40).freq_hz, 50, kEps);
  EXPECT_NEAR(m.map(40).amplitude, 0.0750, 1e-4);
  EXPECT_NEAR(m.map(76).freq_hz, 250, kEps);
  EXPECT_NEAR(m.map(76).amplitude, 1.0, kEps);
  EXPECT_NEAR(m.map(58).freq_hz, 150, kEps);  // half-way key
  // Keys outside the track's range stay on its ends.
  EXPECT_NEAR(m.map(0).freq_hz, 50, kEps);
  EXPECT_NEAR(m.map(127).freq_hz, 250, kEps);
  EXPECT_NEAR(m.map(127).amplitude, 1.0, kEps);
}

TEST(PaperMode, OneKeyAndEmptyTrackGetTheMiddle) {
  const Ranges r;
  const double mid_amp = db_to_linear_ref((7.5 + 30) / 2, 30);  // n = k_ε/2 → a_dB = 18.75
  for (const KeySet& keys : {make_keys({60}), KeySet{}}) {
    const Mapper m(Mode::paper, r, keys);
    for (int k : {0, 60, 127}) {
      const Haptic h = m.map(static_cast<std::uint8_t>(k));
      EXPECT_NEAR(h.freq_hz, 150, kEps);
      EXPECT_NEAR(h.amplitude, mid_amp, kEps);
    }
    EXPECT_EQ(m.jnd_steps(), 0.0);
  }
}

TEST(RankMode, ConsecutiveRanksHaveAConstantRatio) {
  std::mt19937_64 rng(13);
  const Ranges r;
  for (int trial = 0; trial < 300; ++trial) {
    const std::vector<int> keys = random_keys(rng);
    if (keys.size() < 2) continue;
    const Mapper m(Mode::rank, r, make_keys(keys));
    const double steps = static_cast<double>(keys.size() - 1);
    const double ratio = std::pow(r.f_max_hz / r.f_min_hz, 1 / steps);
    const double db_step = (r.a_max_db - r.a_min_db) / steps;
    EXPECT_NEAR(m.map(static_cast<std::uint8_t>(keys.front())).freq_hz, r.f_min_hz, kEps);
    EXPECT_NEAR(m.map(static_cast<std::uint8_t>(keys.back())).freq_hz, r.f_max_hz, kEps);
    for (std::size_t i = 1; i < keys.size(); ++i) {
      const Haptic lo = m.map(static_cast<std::uint8_t>(keys[i - 1]));
      const Haptic hi = m.map(static_cast<std::uint8_t>(keys[i]));
      EXPECT_NEAR(hi.freq_hz / lo.freq_hz, ratio, kEps);
      EXPECT_NEAR(20 * std::log10(hi.amplitude / lo.amplitude), db_step, kEps);
    }
    EXPECT_NEAR(m.jnd_steps(), std::log(5.0) / std::log(1.18), kEps);
  }
}

TEST(RankMode, OneKeyIsTheGeometricMiddle) {
  const Ranges r;
  const Mapper m(Mode::rank, r, make_keys({70}));
  EXPECT_NEAR(m.map(70).freq_hz, std::sqrt(50.0 * 250.0), kEps);
  EXPECT_NEAR(m.map(70).amplitude, db_to_linear_ref(18.75, 30), kEps);
  const Mapper empty(Mode::rank, r, KeySet{});
  EXPECT_NEAR(empty.map(70).freq_hz, std::sqrt(50.0 * 250.0), kEps);
}

TEST(RankMode, AbsentKeySitsBetweenItsNeighbours) {
  const Mapper m(Mode::rank, Ranges{}, make_keys({40, 50, 60}));
  const double f40 = m.map(40).freq_hz, f45 = m.map(45).freq_hz, f50 = m.map(50).freq_hz;
  EXPECT_GT(f45, f40);
  EXPECT_LT(f45, f50);
  EXPECT_NEAR(f45, std::sqrt(f40 * f50), kEps);  // half a rank: the geometric middle
}

// 2013 paper: note_step = unique·(k − k_min)/(Δk + 1) (its Eq. 3), normalised by the number of distinct
// keys so that keyfreq = 60 + note_step'·140 Hz and keyamp = 3.8 + note_step'·1.2 stay in range.
TEST(Legacy2013Mode, NormalisedNoteStepStaysInRange) {
  std::mt19937_64 rng(17);
  for (int trial = 0; trial < 300; ++trial) {
    const std::vector<int> keys = random_keys(rng);
    const Mapper m(Mode::legacy2013, Ranges{}, make_keys(keys));
    const double unique = static_cast<double>(keys.size());
    for (int k : keys) {
      const double note_step = unique * (k - keys.front()) / (keys.back() - keys.front() + 1);  // Eq. 3
      const double normalised = note_step / unique;
      const Haptic h = m.map(static_cast<std::uint8_t>(k));
      EXPECT_NEAR(h.freq_hz, 60 + normalised * 140, kEps);
      EXPECT_NEAR(h.amplitude, (3.8 + normalised * 1.2) / 5.0, kEps);
      EXPECT_GE(h.freq_hz, 60.0);
      EXPECT_LT(h.freq_hz, 200.0);
      EXPECT_GE(h.amplitude, 0.76 - kEps);
      EXPECT_LT(h.amplitude, 1.0);
    }
    EXPECT_NEAR(m.map(static_cast<std::uint8_t>(keys.front())).freq_hz, 60, kEps);
  }
  const Mapper empty(Mode::legacy2013, Ranges{}, KeySet{});
  EXPECT_NEAR(empty.map(60).freq_hz, 130, kEps);
  // Ranges given by the user do not move the 2013 mapping.
  Ranges other;
  other.f_min_hz = 10;
  other.f_max_hz = 20;
  EXPECT_NEAR(Mapper(Mode::legacy2013, other, make_keys({50, 51})).map(51).freq_hz, 130, kEps);
}

TEST(ConstantMode, AlwaysTwoHundredFiftyHertzFullScale) {
  std::mt19937_64 rng(19);
  for (int trial = 0; trial < 50; ++trial) {
    const Mapper m(Mode::constant, Ranges{}, make_keys(random_keys(rng)));
    for (int k = 0; k < 128; ++k) {
      const Haptic h = m.map(static_cast<std::uint8_t>(k));
      EXPECT_EQ(h.freq_hz, 250.0);
      EXPECT_EQ(h.amplitude, 1.0);
    }
    EXPECT_EQ(m.jnd_steps(), 0.0);
  }
  EXPECT_EQ(Mapper(Mode::constant, Ranges{}, KeySet{}).map(0).freq_hz, 250.0);
}

TEST(JndSteps, CountsEighteenPercentStepsOfTheUsedFrequencies) {
  const KeySet keys = make_keys({48, 60, 72});
  EXPECT_NEAR(Mapper(Mode::paper, Ranges{}, keys).jnd_steps(), std::log(250.0 / 50.0) / std::log(1.18), kEps);
  // legacy2013 uses 60 Hz … 60 + 140·24/25 Hz.
  EXPECT_NEAR(Mapper(Mode::legacy2013, Ranges{}, keys).jnd_steps(),
              std::log((60 + 140 * 24.0 / 25.0) / 60) / std::log(1.18), kEps);
  EXPECT_EQ(Mapper(Mode::paper, Ranges{}, make_keys({60})).jnd_steps(), 0.0);
}

TEST(Ranges, InvalidRangesFallBackToDefaults) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(hmp::mapping::valid(Ranges{}));
  std::vector<Ranges> bad(5);
  bad[0].f_min_hz = 0;
  bad[1].f_min_hz = 300;  // above f_max
  bad[2].f_max_hz = nan;
  bad[3].a_min_db = 40;  // above a_max
  bad[4].a_max_db = std::numeric_limits<double>::infinity();
  const KeySet keys = make_keys({40, 80});
  for (const Ranges& r : bad) {
    EXPECT_FALSE(hmp::mapping::valid(r));
    for (Mode mode : {Mode::paper, Mode::rank}) {
      const Mapper m(mode, r, keys);
      EXPECT_NEAR(m.map(40).freq_hz, 50, kEps);
      EXPECT_NEAR(m.map(80).freq_hz, 250, kEps);
    }
  }
  Ranges flat;  // a single frequency is a valid range
  flat.f_min_hz = flat.f_max_hz = 100;
  EXPECT_TRUE(hmp::mapping::valid(flat));
  EXPECT_NEAR(Mapper(Mode::rank, flat, keys).map(80).freq_hz, 100, kEps);
}

TEST(Modes, EveryKeyOfEveryModeIsFiniteAndInRange) {
  std::mt19937_64 rng(23);
  for (int trial = 0; trial < 200; ++trial) {
    const KeySet keys = trial == 0 ? KeySet{} : make_keys(random_keys(rng));
    for (Mode mode : {Mode::paper, Mode::rank, Mode::constant, Mode::legacy2013}) {
      const Mapper m(mode, Ranges{}, keys);
      for (int k = 0; k < 256; ++k) {
        const Haptic h = m.map(static_cast<std::uint8_t>(k));
        ASSERT_TRUE(std::isfinite(h.freq_hz) && std::isfinite(h.amplitude));
        ASSERT_GE(h.freq_hz, 50.0);
        ASSERT_LE(h.freq_hz, 250.0);
        ASSERT_GE(h.amplitude, 0.0750 - 1e-4);
        ASSERT_LE(h.amplitude, 1.0);
      }
      ASSERT_TRUE(std::isfinite(m.jnd_steps()));
    }
  }
}

TEST(Modes, NamesRoundTripCaseInsensitively) {
  const char* names[] = {"paper", "rank", "constant", "legacy2013"};
  const Mode modes[] = {Mode::paper, Mode::rank, Mode::constant, Mode::legacy2013};
  for (int i = 0; i < 4; ++i) {
    EXPECT_STREQ(hmp::mapping::name(modes[i]), names[i]);
    Mode found = Mode::paper;
    EXPECT_TRUE(hmp::mapping::find_mode(names[i], found));
    EXPECT_EQ(found, modes[i]);
  }
  Mode found = Mode::paper;
  EXPECT_TRUE(hmp::mapping::find_mode("LEGACY2013", found));
  EXPECT_EQ(found, Mode::legacy2013);
  EXPECT_TRUE(hmp::mapping::find_mode("Rank", found));
  EXPECT_EQ(found, Mode::rank);
  for (const char* bad : {"", "papers", "linear", "legacy"}) EXPECT_FALSE(hmp::mapping::find_mode(bad, found));
  EXPECT_FALSE(hmp::mapping::find_mode(nullptr, found));
}

}  // namespace
