// The three sine implementations against std::sin in double over every 2^12-th phase (2^20 points)
// and a million random phases.
#include "shared/synth/sine.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <random>

namespace {

using namespace hmp::synth;

constexpr double kTwoPi = 2 * std::numbers::pi;

double reference(std::uint32_t phase) { return std::sin(kTwoPi * (static_cast<double>(phase) / 4294967296.0)); }

double max_error(SineImpl impl) {
  double worst = 0.0;
  const auto check = [&](std::uint32_t p) {
    worst = std::max(worst, std::fabs(static_cast<double>(sine(impl, p)) - reference(p)));
  };
  for (std::uint32_t i = 0; i < (1u << 20); ++i) check(i << 12);
  std::mt19937 rng(7);
  for (int i = 0; i < 1000000; ++i) check(static_cast<std::uint32_t>(rng()));
  return worst;
}

void record_error(double e) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3e", e);
  ::testing::Test::RecordProperty("max_error", text);
}

// Bounds from the method plus float rounding: sinf after the argument is formed in float (up to ~3 float
// roundings of an argument near π, ≈ 1.2e-7 each); linear interpolation of 1024 samples per turn,
// (2π/1024)²/8 = 4.71e-6; the degree-7 minimax fit, 6.0e-7, plus ≈ 1.5e-7 of float evaluation.
TEST(Sine, LibmError) {
  const double e = max_error(SineImpl::libm);
  record_error(e);
  EXPECT_LT(e, 5e-7);
}

TEST(Sine, TableError) {
  const double e = max_error(SineImpl::table);
  record_error(e);
  EXPECT_LT(e, 4.8e-6);
  EXPECT_GT(e, 4.5e-6);  // the interpolation error is really there: the table is the plain sine samples
}

TEST(Sine, PolyError) {
  const double e = max_error(SineImpl::poly);
  record_error(e);
  EXPECT_LT(e, 1e-6);
}

TEST(Sine, DispatchAndNames) {
  for (std::uint32_t p : {0u, 1u, 0x12345678u, 0x80000000u, 0xFFFFFFFFu}) {
    EXPECT_EQ(sine(SineImpl::libm, p), sine_libm(p));
    EXPECT_EQ(sine(SineImpl::table, p), sine_table(p));
    EXPECT_EQ(sine(SineImpl::poly, p), sine_poly(p));
  }
  EXPECT_STREQ(name(SineImpl::libm), "libm");
  EXPECT_STREQ(name(SineImpl::table), "table");
  EXPECT_STREQ(name(SineImpl::poly), "poly");
}

// Phase 0 must give exactly 0 (a note starts silent and continuous); the table hits the quarter turns exactly.
TEST(Sine, ExactPoints) {
  for (SineImpl impl : {SineImpl::libm, SineImpl::table, SineImpl::poly}) EXPECT_EQ(sine(impl, 0), 0.0f) << name(impl);
  EXPECT_EQ(sine_table(0x40000000u), 1.0f);
  EXPECT_EQ(sine_table(0x80000000u), 0.0f);
  EXPECT_EQ(sine_table(0xC0000000u), -1.0f);
}

// Odd symmetry and |sin| ≤ 1 + method error everywhere, including the wrap at the top of the phase.
TEST(Sine, SymmetryAndRange) {
  std::mt19937 rng(8);
  for (SineImpl impl : {SineImpl::libm, SineImpl::table, SineImpl::poly}) {
    for (int i = 0; i < 100000; ++i) {
      const auto p = static_cast<std::uint32_t>(rng());
      const float a = sine(impl, p), b = sine(impl, 0u - p);
      ASSERT_NEAR(a, -b, 1e-6f) << name(impl) << " " << p;
      ASSERT_LE(std::fabs(a), 1.000001f) << name(impl) << " " << p;
    }
    ASSERT_NEAR(sine(impl, 0xFFFFFFFFu), 0.0f, 1e-8f) << name(impl);
  }
}

}  // namespace
