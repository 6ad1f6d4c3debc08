// Frequency and amplitude representation (design §7, §9): Q12.20 Hz on the wire, a 64-bit phase
// accumulator in the voice. References use exact 128-bit integer arithmetic.
#include "shared/synth/frequency.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>

namespace {

using namespace hmp::synth;
using u128 = unsigned __int128;

constexpr double kTwoPi = 2 * std::numbers::pi;
constexpr double kTwo64 = 18446744073709551616.0;

// floor(f · 2^44 / fs) mod 2^64, straight from the definition.
std::uint64_t reference_increment(std::uint32_t f_q20, std::uint32_t fs) {
  return static_cast<std::uint64_t>((static_cast<u128>(f_q20) << 44) / fs);
}

// Distance in turns between the accumulator (2^64 = one turn) and the exact phase f_q20·n / (2^20·fs)
// mod 1, computed on integers so the reference itself carries no rounding.
double accumulator_error_turns(std::uint64_t acc, std::uint32_t f_q20, std::uint32_t fs, std::uint64_t n) {
  const u128 den = static_cast<u128>(fs) << 20;  // exact phase = num / den turns
  const u128 num = (static_cast<u128>(f_q20) * n) % den;
  const u128 lhs = static_cast<u128>(acc) * den;  // acc/2^64 vs num/den, both scaled by 2^64·den
  const u128 rhs = num << 64;
  u128 diff = lhs > rhs ? lhs - rhs : rhs - lhs;
  const u128 full = den << 64;              // one turn
  if (diff > full / 2) diff = full - diff;  // circular distance
  return static_cast<double>(diff) / static_cast<double>(full);
}

TEST(FreqToQ20, RoundsToNearestLsb) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> hz(0.0, kFreqMaxHz);
  for (int i = 0; i < 100000; ++i) {
    const double f = hz(rng);
    const std::uint32_t q = freq_to_q20(f);
    const double err = std::fabs(q20_to_hz(q) - f);
    ASSERT_LE(err, 0.5 * kFreqLsbHz) << f;
    // No neighbour is closer.
    if (q > 0) {
      ASSERT_GE(std::fabs(q20_to_hz(q - 1) - f), err) << f;
    }
    if (q < 0xFFFFFFFFu) {
      ASSERT_GE(std::fabs(q20_to_hz(q + 1) - f), err) << f;
    }
  }
}

TEST(FreqToQ20, ExactValuesAndTies) {
  EXPECT_EQ(freq_to_q20(1.0), 1u << 20);
  EXPECT_EQ(freq_to_q20(250.0), 250u << 20);
  EXPECT_EQ(freq_to_q20(kFreqLsbHz), 1u);
  EXPECT_EQ(freq_to_q20(0.5 * kFreqLsbHz), 1u);  // half an LSB rounds up
  EXPECT_EQ(freq_to_q20(0.49999 * kFreqLsbHz), 0u);
  EXPECT_EQ(freq_to_q20(100.0 + 2.5 * kFreqLsbHz), (100u << 20) + 3u);
  for (std::uint32_t q : {1u, 12345u, 0x7FFFFFFFu, 0xFFFFFFFEu, 0xFFFFFFFFu}) EXPECT_EQ(freq_to_q20(q20_to_hz(q)), q);
}

TEST(FreqToQ20, Extremes) {
  EXPECT_EQ(freq_to_q20(0.0), 0u);
  EXPECT_EQ(freq_to_q20(-0.0), 0u);
  EXPECT_EQ(freq_to_q20(-1.0), 0u);
  EXPECT_EQ(freq_to_q20(-std::numeric_limits<double>::infinity()), 0u);
  EXPECT_EQ(freq_to_q20(std::numeric_limits<double>::quiet_NaN()), 0u);
  EXPECT_EQ(freq_to_q20(-std::numeric_limits<double>::quiet_NaN()), 0u);
  EXPECT_EQ(freq_to_q20(std::numeric_limits<double>::denorm_min()), 0u);
  EXPECT_EQ(freq_to_q20(kFreqMaxHz), 0xFFFFFFFFu);
  EXPECT_EQ(freq_to_q20(4096.0), 0xFFFFFFFFu);
  EXPECT_EQ(freq_to_q20(1e300), 0xFFFFFFFFu);
  EXPECT_EQ(freq_to_q20(std::numeric_limits<double>::infinity()), 0xFFFFFFFFu);
  EXPECT_DOUBLE_EQ(q20_to_hz(0xFFFFFFFFu), kFreqMaxHz);
}

TEST(PhaseIncrement, EqualsExactFloorForRandomValues) {
  std::mt19937_64 rng(2);
  std::uniform_int_distribution<std::uint32_t> freq(0, 0xFFFFFFFFu);
  std::uniform_int_distribution<std::uint32_t> rate(1000, 10000);
  for (int i = 0; i < 200000; ++i) {
    const std::uint32_t f = freq(rng), fs = rate(rng);
    ASSERT_EQ(phase_increment(f, fs), reference_increment(f, fs)) << f << " @ " << fs;
  }
}

TEST(PhaseIncrement, ExtremeOperands) {
  for (std::uint32_t fs : {1u, 2u, 3u, 999u, 1000u, 10000u, 48000u, 0x7FFFFFFFu, 0xFFFFFFFFu})
    for (std::uint32_t f : {0u, 1u, 2u, 0x000FFFFFu, 0x00100000u, 0x7FFFFFFFu, 0xFFFFFFFEu, 0xFFFFFFFFu})
      EXPECT_EQ(phase_increment(f, fs), reference_increment(f, fs)) << f << " @ " << fs;
  EXPECT_EQ(phase_increment(0xFFFFFFFFu, 0), 0u);
  // 250 Hz at 1 kHz is a quarter turn per tick, exactly.
  EXPECT_EQ(phase_increment(250u << 20, 1000), std::uint64_t{1} << 62);
}

// One hour of ticks, simulated step by step, against the exact phase. Each increment is floored, so the
// accumulator may lag by < 2^-64 turn per tick: < 2e-13 turn after 3.6e6 ticks (1 kHz) and < 2e-12
// after 3.6e7 (10 kHz), i.e. ≤ 1.2e-11 rad — no drift that any test or finger could see.
TEST(PhaseAccumulator, NoDriftOverOneHour) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> hz(1.0, 4000.0);
  for (std::uint32_t fs : {1000u, 10000u}) {
    const std::uint64_t ticks = 3600ull * fs;
    const double bound = static_cast<double>(ticks) / kTwo64;
    for (int trial = 0; trial < 3; ++trial) {
      const std::uint32_t f = freq_to_q20(hz(rng));
      const std::uint64_t inc = phase_increment(f, fs);
      std::uint64_t acc = 0;
      for (std::uint64_t n = 0; n < ticks; ++n) {
        acc += inc;
        asm volatile("" : "+r"(acc));  // keep the compiler from folding the loop into one multiply
      }
      EXPECT_EQ(acc, static_cast<std::uint64_t>(static_cast<u128>(inc) * ticks));
      const double err = accumulator_error_turns(acc, f, fs, ticks);
      EXPECT_LT(err, bound) << f << " @ " << fs;
      if (fs == 1000) {
        EXPECT_LT(err, 1e-12);
      }
    }
  }
}

// Jump ahead: the accumulator after n ticks is n·inc mod 2^64; check many frequencies and hours.
TEST(PhaseAccumulator, JumpAheadMatchesExactPhase) {
  std::mt19937_64 rng(4);
  std::uniform_int_distribution<std::uint32_t> freq(1, 0xFFFFFFFFu);
  std::uniform_int_distribution<std::uint32_t> rate(1000, 10000);
  for (int i = 0; i < 20000; ++i) {
    const std::uint32_t f = freq(rng), fs = rate(rng);
    const std::uint64_t ticks = 3600ull * fs;
    const auto acc = static_cast<std::uint64_t>(static_cast<u128>(phase_increment(f, fs)) * ticks);
    ASSERT_LT(accumulator_error_turns(acc, f, fs, ticks), static_cast<double>(ticks) / kTwo64) << f << " @ " << fs;
  }
}

// The represented frequency (Q12.20 on the wire, then the increment) against the requested one: the
// phase stays within 1e-4 rad over a 10 s note (design §7).
TEST(PhaseAccumulator, RepresentedFrequencyKeepsPhaseOverTenSeconds) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> hz(1.0, 4000.0);
  double worst = 0.0;
  for (std::uint32_t fs : {1000u, 10000u}) {
    for (int trial = 0; trial < 100; ++trial) {
      const double f = hz(rng);
      const std::uint64_t inc = phase_increment(freq_to_q20(f), fs);
      std::uint64_t acc = 0;
      for (std::uint64_t n = 1; n <= 10ull * fs; ++n) {
        acc += inc;
        if (n % 97 != 0 && n != 10ull * fs) continue;
        const double exact = f * static_cast<double>(n) / fs;  // turns
        double d = static_cast<double>(acc) / kTwo64 - (exact - std::floor(exact));
        d -= std::round(d);
        worst = std::max(worst, std::fabs(d) * kTwoPi);
      }
    }
  }
  EXPECT_LT(worst, 1e-4);
  // The analysis in frequency.hpp: ½ LSB = 4.8e-7 Hz → 3.0e-5 rad in 10 s. The test must see it.
  EXPECT_LT(worst, 0.5 * kFreqLsbHz * 10.0 * kTwoPi * 1.001);
  EXPECT_GT(worst, 0.0);
}

TEST(Amplitude, RoundsClampsAndRejectsNaN) {
  EXPECT_EQ(amp_to_q16(0.0), 0u);
  EXPECT_EQ(amp_to_q16(1.0), 65535u);
  EXPECT_EQ(amp_to_q16(1.5), 65535u);
  EXPECT_EQ(amp_to_q16(1e300), 65535u);
  EXPECT_EQ(amp_to_q16(std::numeric_limits<double>::infinity()), 65535u);
  EXPECT_EQ(amp_to_q16(-0.5), 0u);
  EXPECT_EQ(amp_to_q16(std::numeric_limits<double>::quiet_NaN()), 0u);
  EXPECT_EQ(amp_to_q16(0.5), 32768u);  // 32767.5 rounds up
  EXPECT_EQ(q16_to_amp(65535), 1.0f);
  EXPECT_EQ(q16_to_amp(0), 0.0f);
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> amp(0.0, 1.0);
  for (int i = 0; i < 100000; ++i) {
    const double a = amp(rng);
    const std::uint16_t q = amp_to_q16(a);
    ASSERT_LE(std::fabs(q / kAmpFullScale - a), 0.5 / kAmpFullScale + 1e-15) << a;
    ASSERT_NEAR(static_cast<double>(q16_to_amp(q)), q / kAmpFullScale, 1e-7);
  }
}

}  // namespace
