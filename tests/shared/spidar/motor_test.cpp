// Tension → duty (shared/spidar/motor) against the DC motor equations of design §12 written out here:
// electrical L di/dt = V − R i − Ke ω, mechanical J ω' = Kt i − r T − b ω; steady state at constant ω.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>

#include "shared/spidar/motor.hpp"

namespace {

using namespace hmp::spidar;

// RE-max 24 class (design §11).
constexpr double kKt = 0.0213, kR = 6.5, kV = 12.0, kRadius = 0.005;

// The tension a duty holds in steady state at winding speed ω: i = (dV − Ke ω)/R, T = (Kt i − b ω)/r.
double steady_tension(double duty, double omega, double b = 0) {
  const double current = (duty * kV - kKt * omega) / kR;
  return (kKt * current - b * omega) / kRadius;
}

TEST(SpidarMotor, RoundTripThroughTheMotorEquations) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> tension(0, 7.5), omega(-60, 60), friction(0, 2e-5);
  const MotorModel<float> motor_f;
  const MotorModel<double> motor_d;
  double worst_f = 0;
  int checked = 0;
  for (int k = 0; k < 100000; ++k) {
    const double t = tension(rng), w = omega(rng);
    Flags flags_d = 0, flags_f = 0;
    const double dd = motor_d.duty(t, w, flags_d);
    const float df = motor_f.duty(static_cast<float>(t), static_cast<float>(w), flags_f);
    if (flags_d & flag::saturated) {
      EXPECT_EQ(std::fabs(dd), 1.0);
      continue;
    }
    ASSERT_EQ(flags_d, 0);
    ASSERT_NEAR(steady_tension(dd, w), t, 1e-12);
    if (!(flags_f & flag::saturated))
      worst_f = std::max(worst_f, std::fabs(steady_tension(static_cast<double>(df), w) - t));
    ++checked;
  }
  std::printf("  float round trip: max tension error %.3e N over %d unsaturated cases\n", worst_f, checked);
  EXPECT_GT(checked, 50000);
  EXPECT_LT(worst_f, 5e-6);  // measured 8.2e-7 N: float rounding of the duty (~6e-8) times the stall tension 7.9 N

  // With viscous friction compensated.
  for (int k = 0; k < 1000; ++k) {
    const double b = friction(rng), t = tension(rng) * 0.5, w = omega(rng) * 0.5;
    MotorParams<double> p;
    p.viscous_friction = b;
    Flags flags = 0;
    const double d = MotorModel<double>(p).duty(t, w, flags);
    ASSERT_EQ(flags, 0);
    ASSERT_NEAR(steady_tension(d, w, b), t, 1e-12);
  }
}

TEST(SpidarMotor, Facts) {
  const MotorModel<double> motor;
  // Stall: the full 12 V holds V·Kt/(R·r) = 7.86 N — above the QP's t_max of 6 N, with ~24% left over for
  // back-EMF while the string reels in.
  EXPECT_NEAR(motor.stall_tension(), kV * kKt / (kR * kRadius), 1e-12);
  EXPECT_GT(motor.stall_tension(), 6.0);
  // 512 lines × 4 on a 5 mm pulley.
  EXPECT_NEAR(motor.metres_per_count(), 2 * std::numbers::pi * kRadius / 2048, 1e-15);
  EXPECT_NEAR(motor.metres_per_count(), 15.34e-6, 0.01e-6);
  // Counts grow as string pays out: +10 counts in a 1 ms tick is the pulley unwinding (negative ω).
  EXPECT_NEAR(motor.winding_speed(10, 1000.0), -10 * 2 * 3.14159265358979 / 2048 * 1000, 1e-9);
  EXPECT_NEAR(motor.winding_speed(-3, 10000.0), 3 * 2 * 3.14159265358979 / 2048 * 10000, 1e-9);
}

TEST(SpidarMotor, BackEmfCompensationSign) {
  const MotorModel<float> motor;
  Flags flags = 0;
  const float still = motor.duty(2.0f, 0.0f, flags);
  const float reeling_in = motor.duty(2.0f, 30.0f, flags);   // grip moving towards the motor
  const float paying_out = motor.duty(2.0f, -30.0f, flags);  // user pulling the string out
  EXPECT_EQ(flags, 0);
  EXPECT_GT(reeling_in, still);  // the back-EMF opposes the drive: more voltage for the same current
  EXPECT_LT(paying_out, still);
  EXPECT_NEAR(static_cast<double>(reeling_in - still), kKt * 30 / kV, 1e-6);
  EXPECT_NEAR(static_cast<double>(still - paying_out), kKt * 30 / kV, 1e-6);
  // Pulled out fast enough, holding even 0.3 N takes a reverse voltage (the motor acts as a generator).
  EXPECT_LT(motor.duty(0.3f, -100.0f, flags), 0.0f);
}

TEST(SpidarMotor, SaturationAndBadInput) {
  const MotorModel<float> motor;
  Flags flags = 0;
  EXPECT_EQ(motor.duty(100.0f, 0.0f, flags), 1.0f);
  EXPECT_TRUE(flags & flag::saturated);
  flags = 0;
  EXPECT_EQ(motor.duty(0.3f, -2000.0f, flags), -1.0f);
  EXPECT_TRUE(flags & flag::saturated);
  flags = 0;
  EXPECT_EQ(motor.duty(6.0f, 1e30f, flags), 1.0f);
  EXPECT_TRUE(flags & flag::saturated);
  // A string cannot push: negative tension is treated as zero.
  flags = 0;
  EXPECT_EQ(motor.duty(-5.0f, 0.0f, flags), 0.0f);
  EXPECT_EQ(flags, 0);
  // Non-finite tension: no drive at all; non-finite speed: drive without back-EMF compensation.
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  flags = 0;
  EXPECT_EQ(motor.duty(nan, 0.0f, flags), 0.0f);
  EXPECT_TRUE(flags & flag::invalid_input);
  flags = 0;
  EXPECT_EQ(motor.duty(inf, 0.0f, flags), 0.0f);
  EXPECT_TRUE(flags & flag::invalid_input);
  flags = 0;
  EXPECT_EQ(motor.duty(2.0f, nan, flags), motor.duty(2.0f, 0.0f, flags));
  EXPECT_TRUE(flags & flag::invalid_input);
  // Whatever comes in, the duty is finite and within ±1.
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> wild(-1e6f, 1e6f);
  for (int k = 0; k < 10000; ++k) {
    const float d = motor.duty(wild(rng), wild(rng), flags);
    ASSERT_TRUE(std::isfinite(d) && d >= -1.0f && d <= 1.0f);
  }
}

// The steady-state model is right within one tick: with the winding's electrical time constant L/R ≈ 0.1 ms
// (design §12), the current settles to e^-10 of a step in 1 ms. Integrated here with fine explicit Euler.
TEST(SpidarMotor, CurrentSettlesWithinOneTick) {
  const double inductance = 0.1e-3 * kR;  // L = τ·R
  const MotorModel<double> motor;
  Flags flags = 0;
  const double omega = 20.0, target = 4.0;
  const double duty = motor.duty(target, omega, flags);
  double current = 0;  // from rest at the start of the tick
  const double dt = 1e-8;
  for (int n = 0; n < 100000; ++n) current += dt * (duty * kV - kR * current - kKt * omega) / inductance;
  const double tension = kKt * current / kRadius;
  EXPECT_NEAR(tension, target, target * 1e-4);
}

}  // namespace
