// Plant simulator integrators (boards/sim/plant/integrators): each converges to a fine-step RK4 solution
// at its order, the default (exponential) and ROS2 stay stable at one step per tick for string stiffness
// 10³–10⁷ N/m at 1 and 10 kHz, an explicit method past its stable step is reported unstable, and the
// translation-only model agrees with the 6-DOF one when no torque acts.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "boards/sim/plant/plant.hpp"
#include "tests/boards/sim/plant_reference.hpp"

namespace {

using namespace hmp::sim::plant;

constexpr double kTwoPi = 2 * std::numbers::pi;

// Smooth regime: every string stays taut (1 N bias, duties ±10% around the hold), constant duties, so
// the solution is smooth and each method shows its asymptotic order.
struct Snapshot {
  double tension[8];
  Vec3d position;
};

Snapshot integrate(Method m, double step, double span) {
  PlantParams p;
  p.stepper.method = m;
  p.stepper.max_step = step;
  Plant plant(p);
  plant.reset(1.0);
  double duty[8];
  for (int i = 0; i < 8; ++i) duty[i] = plant.holding_duty(1.0) * (i % 2 ? 1.1 : 0.9);
  plant.step(duty, span);
  Snapshot s{};
  for (int i = 0; i < 8; ++i) s.tension[i] = plant.output().tension[i];
  s.position = plant.position();
  return s;
}

double distance(const Snapshot& a, const Snapshot& b) {
  double e = 0;
  for (int i = 0; i < 8; ++i) e = std::fmax(e, std::fabs(a.tension[i] - b.tension[i]));
  // 1 µm of position counts like 10 mN of tension (the string stiffness).
  return std::fmax(e, 1e4 * hmp::spidar::norm(a.position - b.position));
}

TEST(PlantIntegrators, EachConvergesAtItsOrder) {
  const double span = 2e-3;
  const Snapshot ref = integrate(Method::rk4, span / 8192, span);
  // Halving the step divides the error by 2^order.
  struct Expect {
    Method m;
    double ratio_lo, ratio_hi;
  };
  const Expect expect[] = {{Method::explicit_euler, 1.8, 2.2}, {Method::semi_implicit_euler, 1.8, 2.2},
                           {Method::rk4, 13.0, 19.0},          {Method::linear_implicit_euler, 1.8, 2.2},
                           {Method::rosenbrock2, 3.5, 4.5},    {Method::exponential, 3.5, 4.5}};
  for (const Expect& e : expect) {
    double previous = 0;
    for (int n = 64; n <= 256; n *= 2) {
      const double err = distance(integrate(e.m, span / n, span), ref);
      if (previous > 0) {
        const double ratio = previous / err;
        std::printf("  %-22s h = %6.2f µs: error %.3e, ratio %.2f\n", std::string(method_name(e.m)).c_str(),
                    span / n * 1e6, err, ratio);
        EXPECT_GT(ratio, e.ratio_lo) << method_name(e.m) << " n=" << n;
        EXPECT_LT(ratio, e.ratio_hi) << method_name(e.m) << " n=" << n;
      }
      ASSERT_GT(err, 1e-12) << "error at the round-off floor: the order cannot be seen";
      previous = err;
    }
  }
}

// A 250 Hz vibration on the hold duty (top strings against bottom ones), `seconds` long.
struct VibrationRun {
  bool stable;
  double mean_tension[8];  // over the last half
  double peak_tension;
};

VibrationRun vibrate(PlantParams p, double tick, double seconds) {
  Plant plant(p);
  plant.reset(0.5);
  const double hold = plant.holding_duty(0.5);
  const int ticks = static_cast<int>(std::lround(seconds / tick));
  VibrationRun r{true, {}, 0};
  int averaged = 0;
  for (int k = 0; k < ticks; ++k) {
    const double s = 0.03 * std::sin(kTwoPi * 250.0 * k * tick);
    double duty[8];
    for (int i = 0; i < 8; ++i) duty[i] = hold + (i < 4 ? -s : s);
    const PlantOutput& out = plant.step(duty, tick);
    for (int i = 0; i < 8; ++i) {
      if (!std::isfinite(out.tension[i])) r.stable = false;
      r.peak_tension = std::fmax(r.peak_tension, out.tension[i]);
      if (2 * k >= ticks) r.mean_tension[i] += out.tension[i];
    }
    if (2 * k >= ticks) ++averaged;
  }
  for (double& m : r.mean_tension) m /= averaged;
  r.stable = r.stable && !plant.unstable();
  return r;
}

// The default (exponential) and ROS2 at one step per tick, soft to wire-like strings: no blow-up, and the
// mean tension is the hold tension (the stall equation: the vibration's duty swings average out in a
// linear motor).
TEST(PlantIntegrators, DefaultIsStableAtTheTickForAllStringStiffnesses) {
  ASSERT_EQ(PlantParams{}.stepper.method, Method::exponential);
  for (Method m : {Method::exponential, Method::rosenbrock2}) {
    for (double k : {1e3, 1e4, 1e5, 1e6, 1e7}) {
      for (double tick : {1e-3, 1e-4}) {
        PlantParams p;
        p.string.stiffness = k;
        p.stepper.method = m;
        p.stepper.max_step = tick;  // one step per tick
        const VibrationRun r = vibrate(p, tick, 0.4);
        const std::string what =
            std::string(method_name(m)) + ", k = " + std::to_string(k) + ", tick " + std::to_string(tick);
        EXPECT_TRUE(r.stable) << what;
        double worst = 0;
        for (double t : r.mean_tension) worst = std::fmax(worst, std::fabs(t - 0.5));
        std::printf("  %s: mean tension off by %.2e N, peak %.2f N\n", what.c_str(), worst, r.peak_tension);
        EXPECT_LT(worst, 0.01) << what;
        EXPECT_LT(r.peak_tension, plant_ref::stall_tension(1.0)) << what;
      }
    }
  }
}

TEST(PlantIntegrators, ExplicitMethodsPastTheirStableStepAreFlagged) {
  // The electrical pole −R/L = −10⁴/s bounds explicit Euler at 0.2 ms and RK4 at ~0.28 ms.
  for (Method m : {Method::explicit_euler, Method::semi_implicit_euler, Method::rk4}) {
    PlantParams p;
    p.stepper.method = m;
    p.stepper.max_step = 0.5e-3;
    const VibrationRun r = vibrate(p, 1e-3, 0.1);
    EXPECT_FALSE(r.stable) << method_name(m);
    // ... and within their stable step they are fine.
    p.stepper.max_step = 0.1e-3;
    EXPECT_TRUE(vibrate(p, 1e-3, 0.1).stable) << method_name(m);
  }
  // The flag latches, the outputs stay finite (the last plausible state), and reset() clears it.
  PlantParams p;
  p.stepper.method = Method::explicit_euler;
  p.stepper.max_step = 1e-3;
  Plant plant(p);
  double duty[8];
  for (double& d : duty) d = plant.holding_duty(0.5);
  int first = -1;
  for (int k = 0; k < 50; ++k) {
    const PlantOutput& out = plant.step(duty, 1e-3);
    for (double t : out.tension) {
      ASSERT_TRUE(std::isfinite(t));
    }
    if (out.status == Status::unstable && first < 0) first = k;
    if (first >= 0) {
      ASSERT_EQ(out.status, Status::unstable);
    }
  }
  EXPECT_GE(first, 0);
  EXPECT_LT(first, 10);  // a blow-up by 4× per step crosses the limits within a few steps
  plant.reset();
  EXPECT_FALSE(plant.unstable());
}

// With the strings tied at the grip's centre no string makes a torque, so the 6-DOF grip never turns
// and must move exactly like the translation-only one.
TEST(PlantIntegrators, TranslationOnlyAgreesWithSixDofWithoutTorques) {
  PlantParams p;
  for (auto& a : p.frame.attachment) a = {};
  p.finger.anchor = {0.003, 0.002, -0.004};
  PlantParams t = p;
  t.scene.translation_only = true;
  Plant full(p), translation(t);
  EXPECT_EQ(full.state_size(), 37);
  EXPECT_EQ(translation.state_size(), 30);
  full.reset(0.4);
  translation.reset(0.4);
  double worst = 0;
  for (int k = 0; k < 300; ++k) {
    double duty[8];
    for (int i = 0; i < 8; ++i)
      duty[i] = full.holding_duty(0.4) + 0.05 * std::sin(kTwoPi * (100.0 + 20 * i) * k * 1e-3);
    const PlantOutput& a = full.step(duty, 1e-3);
    const PlantOutput& b = translation.step(duty, 1e-3);
    for (int i = 0; i < 8; ++i) worst = std::fmax(worst, std::fabs(a.tension[i] - b.tension[i]));
    worst = std::fmax(worst, 1e4 * hmp::spidar::norm(full.position() - translation.position()));
  }
  const auto q = full.orientation();
  EXPECT_EQ(q.w, 1.0);
  EXPECT_EQ(q.x, 0.0);
  std::printf("  largest difference %.2e (N, or 0.1 mm)\n", worst);
  EXPECT_LT(worst, 1e-9);
}

// Sub-stepping: step(dt) over n ticks equals one call per tick when the duties are constant.
TEST(PlantIntegrators, SubstepsAreEqualSlicesOfTheTick) {
  PlantParams p;
  p.stepper.max_step = 0.3e-3;  // 1 ms → 4 sub-steps of 0.25 ms
  Plant a(p), b(p);
  p.stepper.max_step = 0.25e-3;
  Plant c(p);
  double duty[8];
  for (double& d : duty) d = a.holding_duty(0.6);
  for (int k = 0; k < 20; ++k) {
    a.step(duty, 1e-3);
    c.step(duty, 1e-3);
  }
  for (int i = 0; i < 8; ++i) EXPECT_EQ(a.output().tension[i], c.output().tension[i]);
  b.step(duty, 1e-3);
  EXPECT_NEAR(b.time(), 1e-3, 1e-18);
}

// The board hands over the firmware's float duties: the same as their double values.
TEST(PlantIntegrators, FloatDutiesAreTheirDoubleValues) {
  Plant a, b;
  float f[8];
  double d[8];
  for (int i = 0; i < 8; ++i) {
    f[i] = 0.01f * static_cast<float>(i + 3);
    d[i] = static_cast<double>(f[i]);
  }
  for (int k = 0; k < 10; ++k) {
    a.step(f, 1e-3);
    b.step(d, 1e-3);
  }
  for (int i = 0; i < 8; ++i) EXPECT_EQ(a.output().counts[i], b.output().counts[i]);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(a.output().tension[i], b.output().tension[i]);
}

}  // namespace
