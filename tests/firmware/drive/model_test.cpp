// The drive's dynamics compensator (firmware/drive_model.cpp) on its own, from soft to steel-stiff strings
// (10³ to 10⁷ N/m at 1 kHz), against steady states worked out here in double: at rest its motor force is
// the target and its winding speed zero; on a ramp of the targets both follow the continuous model exactly.
// Stiff strings make the string part stiff (the stretch follows the tension within c/k, 0.2 µs at 10⁷ N/m)
// and its output rows cancel to a few parts in 10⁶: computed in float, the motor force at rest was
// 0.32 × the target at 10⁷ N/m and the pre-emphasis 1.45.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "firmware/drive_model.hpp"

namespace hmp::test {
namespace {

constexpr int kStrings = fw::DriveCompensator::kStrings;
constexpr std::uint32_t kTickHz = 1000;
constexpr double kStiffnesses[] = {1e3, 1e4, 1e5, 1e6, 3e6, 1e7};

fw::DriveCompensator make(double stiffness) {
  fw::PlantModel plant;
  plant.string_stiffness = static_cast<float>(stiffness);
  fw::DriveCompensator c;
  c.configure(plant, spidar::MotorParams<float>{}, fw::CompensatorConfig{}, kTickHz);
  return c;
}

// One tick with every string at `target` and the grip still; the split drive's step (no encoder speed, so
// the speed out is the model's alone).
void step(fw::DriveCompensator& c, double target, double& force, double& speed) {
  float t[kStrings], along[kStrings] = {}, f[kStrings], s[kStrings];
  for (float& v : t) v = static_cast<float>(target);
  c.step_between(t, 0.0f, along, f, s);
  force = static_cast<double>(f[0]);
  speed = static_cast<double>(s[0]);
  for (int i = 1; i < kStrings; ++i) {
    EXPECT_EQ(f[i], f[0]);
    EXPECT_EQ(s[i], s[0]);
  }
}

// Exact: with a constant target nothing moves, so u = T (no τ_e Ṫ, no inertia, no back-EMF).
TEST(DriveModel, AtRestTheMotorForceIsTheTarget) {
  for (double k : kStiffnesses) {
    for (double tension : {0.1, 0.3132, 5.0}) {
      fw::DriveCompensator c = make(k);
      c.reset(static_cast<float>(tension));
      double force = 0, speed = 0;
      for (int n = 0; n < 50; ++n) {
        step(c, tension, force, speed);
        ASSERT_NEAR(force / tension, 1.0, 1e-4) << "k " << k << " N/m, T " << tension << " N, tick " << n;
        // 10⁻⁵ rad/s per newton of tension: a back-EMF term of 1.4·10⁻⁷ of the tension (b r ω, b = 2.8 N·s/m),
        // float's rounding of the tick's coefficients.
        ASSERT_NEAR(speed, 0.0, 1e-5 * tension) << "k " << k << " N/m, T " << tension << " N, tick " << n;
      }
      if (tension == 0.3132) std::printf("k %.0e N/m: motor force / target at rest %.7f\n", k, force / tension);
    }
  }
}

// Targets on a ramp, a N/s from rest, one value a tick: the tick's input runs from T(n−1) to T(n), so in
// continuous time it is a(t − h). Once R has settled its output lags the input by 2ζ/ω_c, the string
// (c ẋ + k x = T_r) winds at a/k with no acceleration, so u = T_r + τ_e a, averaged over the coming tick:
// a((n − ½)h − 2ζ/ω_c) + τ_e a; the winding speed a/(k r).
TEST(DriveModel, OnARampTheModelFollowsTheContinuousSteadyState) {
  const fw::PlantModel plant;
  const spidar::MotorParams<float> motor;
  const double h = 1.0 / kTickHz, a = 10.0, t0 = 0.3;
  const double wc = static_cast<double>(fw::DriveCompensator::kReferenceCorner) * kTickHz;
  const double lag = 2.0 * static_cast<double>(fw::DriveCompensator::kReferenceDamping) / wc;
  const double tau_e = static_cast<double>(plant.inductance) / static_cast<double>(motor.resistance);
  const double r = static_cast<double>(motor.pulley_radius);
  for (double k : kStiffnesses) {
    fw::DriveCompensator c = make(k);
    c.reset(static_cast<float>(t0));
    double force = 0, speed = 0, worst_force = 0, worst_speed = 0;
    for (int n = 1; n <= 100; ++n) {
      step(c, t0 + a * n * h, force, speed);
      if (n < 40) continue;  // R's transient (and the string's, 20 ms at 10³ N/m) has gone well before
      const double want_force = t0 + a * ((n - 0.5) * h - lag) + tau_e * a;
      const double want_speed = a / (k * r);
      worst_force = std::fmax(worst_force, std::fabs(force - want_force));
      worst_speed = std::fmax(worst_speed, std::fabs(speed - want_speed));
    }
    std::printf("k %.0e N/m, ramp %.0f N/s: worst |u - exact| %.2e N, |speed - exact| %.2e rad/s (exact %.2e)\n", k, a,
                worst_force, worst_speed, a / (k * r));
    // Float's rounding of a 1.3 N target is 10⁻⁷ N; 10⁻⁵ N leaves a margin (with the damper force taken as
    // T_r − k x_s from two float states the error was 3.4·10⁻⁴ N at 10⁷ N/m).
    EXPECT_LT(worst_force, 1e-5) << "k " << k;
    EXPECT_LT(worst_speed, 1e-3 * a / (k * r)) << "k " << k;
  }
}

// The pre-emphasis makes up the string chain's gain at 250 Hz. Stiffer strings leave less between the
// motor and the grip, so the gain settles as the string tends to rigid: 10⁶, 3·10⁶ and 10⁷ N/m agree
// within a fraction of a percent (float gave α = 1.45 at 10⁷ N/m, a chain gain of 0.35).
TEST(DriveModel, ThePreEmphasisSettlesForStiffStrings) {
  const double alpha_1e6 = static_cast<double>(make(1e6).emphasis());
  for (double k : {3e6, 1e7}) {
    const fw::DriveCompensator c = make(k);
    std::printf("k %.0e N/m: chain gain %.5f, pre-emphasis %.5f\n", k, static_cast<double>(c.chain_gain()),
                static_cast<double>(c.emphasis()));
    EXPECT_NEAR(static_cast<double>(c.emphasis()), alpha_1e6, 2e-3) << "k " << k;
    EXPECT_NEAR(static_cast<double>(c.chain_gain()), 1.0, 0.02) << "k " << k;
  }
}

}  // namespace
}  // namespace hmp::test
