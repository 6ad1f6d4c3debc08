// TempoMap and Division (design §4): integer µs per tempo segment, SMPTE including 29.97, no drift, no overflow.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "host/midi/tempo_map.hpp"

using hmp::midi::Division;
using hmp::midi::TempoMap;

namespace {

// Reference: exact rational time in µs, summed segment by segment in long double from the raw points.
long double reference_us(const std::vector<TempoMap::Point>& sorted_points, unsigned tpq, std::uint64_t tick) {
  long double us = 0;
  std::uint64_t at = 0;
  long double tempo = 500000;
  for (const auto& p : sorted_points) {
    if (p.tick > tick) break;
    us += static_cast<long double>(p.tick - at) * tempo / tpq;
    at = p.tick;
    tempo = p.us_per_quarter;
  }
  return us + static_cast<long double>(tick - at) * tempo / tpq;
}

}  // namespace

TEST(MidiDivision, DecodesMetricalAndSmpte) {
  const Division m = Division::from_field(480);
  EXPECT_FALSE(m.smpte);
  EXPECT_EQ(m.ticks_per_quarter, 480);

  // 0xE728: high byte −25 → 25 fps, 40 ticks per frame.
  const Division s25 = Division::from_field(0xE728);
  EXPECT_TRUE(s25.smpte);
  EXPECT_EQ(s25.fps, 25);
  EXPECT_EQ(s25.ticks_per_frame, 40);
  EXPECT_EQ(Division::from_field(0xE850).fps, 24);   // −24
  EXPECT_EQ(Division::from_field(0xE350).fps, 29);   // −29 (29.97)
  EXPECT_EQ(Division::from_field(0xE250).fps, 30);   // −30
  EXPECT_EQ(Division::from_field(0x8001).fps, 128);  // extreme: −128
  EXPECT_EQ(Division::from_field(0xFF01).fps, 1);
}

TEST(MidiTempoMap, DefaultIs120Bpm) {
  const TempoMap map = TempoMap::metrical(96, {});
  EXPECT_EQ(map.micros(0), 0);
  EXPECT_EQ(map.micros(96), 500000);
  EXPECT_EQ(map.micros(96 * 7), 3500000);
  ASSERT_EQ(map.changes().size(), 1u);
  EXPECT_DOUBLE_EQ(map.changes()[0].bpm(), 120.0);
}

TEST(MidiTempoMap, SegmentsMatchIndependentSum) {
  std::vector<TempoMap::Point> pts = {{0, 1000000}, {480, 250000}, {481, 333333}, {10000, 16777215}, {20000, 1}};
  const TempoMap map = TempoMap::metrical(480, pts);
  for (std::uint64_t t :
       {0ull, 1ull, 479ull, 480ull, 481ull, 482ull, 9999ull, 10000ull, 15000ull, 20000ull, 20001ull, 1000000ull}) {
    const long double ref = reference_us(pts, 480, t);
    EXPECT_NEAR(static_cast<double>(map.micros(t)), static_cast<double>(ref), 0.5 + 1e-9) << "tick " << t;
  }
  EXPECT_EQ(map.changes().size(), 5u);
  EXPECT_EQ(map.changes()[1].tick, 480u);
  EXPECT_EQ(map.changes()[1].us, 1000000);
}

TEST(MidiTempoMap, UnsortedPointsAndLastAtSameTickWins) {
  // File order: track 2 said 300000 at tick 96 after track 1 said 250000 there; tick 0 gets 1 s per quarter.
  const TempoMap map = TempoMap::metrical(96, {{96, 250000}, {0, 1000000}, {96, 300000}});
  EXPECT_EQ(map.micros(96), 1000000);
  EXPECT_EQ(map.micros(192), 1300000);
  EXPECT_EQ(map.changes().size(), 2u);
}

TEST(MidiTempoMap, NoDriftOverManyChanges) {
  // 10,000 tempo changes 7 ticks apart with tempi that make every segment's time fractional.
  std::mt19937 rng(7);
  std::vector<TempoMap::Point> pts;
  for (int i = 0; i < 10000; ++i)
    pts.push_back({static_cast<std::uint64_t>(i) * 7, static_cast<std::uint32_t>(400000 + rng() % 300001)});
  const TempoMap map = TempoMap::metrical(997, pts);
  const std::uint64_t last = 10000ull * 7 + 123;
  // Exact reference in integers: Σ Δtick·tempo, divided once.
  unsigned __int128 scaled = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const std::uint64_t next = i + 1 < pts.size() ? pts[i + 1].tick : last;
    scaled += static_cast<unsigned __int128>(next - pts[i].tick) * pts[i].us_per_quarter;
  }
  const auto exact_floor = static_cast<std::int64_t>(scaled / 997);
  const std::int64_t got = map.micros(last);
  EXPECT_GE(got, exact_floor);
  EXPECT_LE(got, exact_floor + 1);
}

TEST(MidiTempoMap, HintedLookupAgreesWithPlain) {
  std::vector<TempoMap::Point> pts;
  for (int i = 1; i < 50; ++i)
    pts.push_back({static_cast<std::uint64_t>(i) * 100, 300000u + static_cast<unsigned>(i) * 1000});
  const TempoMap map = TempoMap::metrical(120, pts);
  std::mt19937_64 rng(3);
  std::size_t hint = 0;
  for (int i = 0; i < 5000; ++i) {
    // Mostly increasing with jumps back, like note end ticks.
    const std::uint64_t t = (i % 7 == 0) ? rng() % 6000 : static_cast<std::uint64_t>(i);
    EXPECT_EQ(map.micros(t, hint), map.micros(t)) << t;
  }
}

TEST(MidiTempoMap, SmpteRates) {
  // 25 fps × 40 ticks per frame = 1 ms per tick.
  EXPECT_EQ(TempoMap::smpte(25, 40).micros(1000), 1000000);
  // 24 fps × 10: 1/240 s per tick.
  EXPECT_EQ(TempoMap::smpte(24, 10).micros(240), 1000000);
  EXPECT_EQ(TempoMap::smpte(24, 10).micros(1), 4167);  // 4166.67 rounds up
  EXPECT_EQ(TempoMap::smpte(30, 4).micros(120), 1000000);
  // 29.97: 30000/1001 frames per second. 30000 frames take 1001 s.
  const TempoMap ntsc = TempoMap::smpte(29, 80);
  EXPECT_EQ(ntsc.micros(30000ull * 80), 1001000000);
  for (std::uint64_t t : {1ull, 7ull, 80ull, 12345ull, 99999999ull}) {
    const double ref = static_cast<double>(t) * 1001.0 / (30000.0 * 80.0) * 1e6;
    EXPECT_NEAR(static_cast<double>(ntsc.micros(t)), ref, 0.501) << t;
  }
  EXPECT_TRUE(ntsc.changes().empty());
  EXPECT_TRUE(ntsc.is_smpte());
}

TEST(MidiTempoMap, DegenerateInputsDoNotDivideByZero) {
  EXPECT_EQ(TempoMap::metrical(0, {}).micros(2), 1000000);  // tpq 0 read as 1
  EXPECT_EQ(TempoMap::smpte(25, 0).micros(25), 1000000);    // tpf 0 read as 1
  EXPECT_EQ(TempoMap::smpte(0, 1).micros(1), 1000000);      // fps 0 read as 1
}

TEST(MidiTempoMap, HugeTicksSaturateInsteadOfOverflowing) {
  const TempoMap slow = TempoMap::metrical(1, {{0, 16777215}});
  const std::int64_t max = std::numeric_limits<std::int64_t>::max();
  EXPECT_EQ(slow.micros(std::numeric_limits<std::uint64_t>::max()), max);
  // 2^40 ticks × 16777215 µs overflows 64 bits in the product but not the result… at tpq 32767:
  const TempoMap big = TempoMap::metrical(32767, {{0, 16777215}});
  const std::uint64_t t = 1ull << 40;
  const long double ref = static_cast<long double>(t) * 16777215.0L / 32767.0L;
  EXPECT_NEAR(static_cast<double>(big.micros(t)), static_cast<double>(ref), 1.0);
  // Monotonic up to saturation.
  std::int64_t prev = 0;
  for (int s = 0; s < 64; ++s) {
    const std::int64_t us = slow.micros(1ull << s);
    EXPECT_GE(us, prev);
    prev = us;
  }
}
