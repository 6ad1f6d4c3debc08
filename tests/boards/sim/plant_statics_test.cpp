// Plant simulator (boards/sim/plant) at rest and at its limits: with constant duties it must settle where
// the motor stall equation and the geometry say (checked with the independent reference geometry of
// tests/shared/spidar/spidar_reference.hpp), slack strings must carry nothing, duties saturate at ±1, the encoders
// count like the real ones, and the grip near the frame edge still balances.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <vector>

#include "boards/sim/plant/dynamics.hpp"
#include "boards/sim/plant/plant.hpp"
#include "tests/boards/sim/plant_reference.hpp"

namespace {

using namespace hmp::sim::plant;
using plant_ref::V3;
namespace flag = hmp::spidar::flag;

constexpr double kTwoPi = 2 * std::numbers::pi;

V3 v3(const Vec3d& v) { return {v.x, v.y, v.z}; }

void run(Plant& plant, const double (&duty)[8], double seconds, double tick = 1e-3) {
  const int ticks = static_cast<int>(std::lround(seconds / tick));
  for (int k = 0; k < ticks; ++k) plant.step(duty, tick);
}

// The band states (Scene::band_force) low-pass the string force at kBandHz. Checked against the same
// Butterworth filter discretised independently (bilinear transform, double precision, 100 kHz) on the
// string force the plant reports, under duties mixing a 100 Hz swing with a 5 kHz square wave: the band
// follows the swing and drops the square wave.
TEST(PlantBand, FollowsAnIndependentButterworthFilterOfTheStringForce) {
  PlantParams p;
  p.scene.band_force = true;
  Plant plant(p);
  plant.reset(0.5);
  const Vec3d f0 = plant.output().string_force;
  EXPECT_EQ(plant.output().band_string_force.y, f0.y);  // at rest the filter holds the force
  const double fs = 1e5, dt = 1.0 / fs, k2 = 2 * fs, w = kBandOmega, r2 = std::sqrt(2.0);
  const double a0 = k2 * k2 + r2 * w * k2 + w * w, a1 = 2 * (w * w - k2 * k2), a2 = k2 * k2 - r2 * w * k2 + w * w;
  const double b0 = w * w, b1 = 2 * w * w, b2 = w * w;
  double x1 = f0.y, x2 = f0.y, y1 = f0.y, y2 = f0.y;
  const double bias = plant.holding_duty(0.5);
  double err2 = 0, var2 = 0, mean = 0, raw2 = 0;
  const int n = 20000;  // 0.2 s
  for (int k = 0; k < n; ++k) {
    const double t = k * dt;
    double duty[8];
    for (int i = 0; i < 8; ++i) {
      const double swing = 0.3 * bias * std::sin(kTwoPi * 100 * t + i);
      const double square = (static_cast<int>(t * 1e4) % 2 == 0 ? 0.3 : -0.3) * bias;
      duty[i] = bias + swing + square;
    }
    const PlantOutput& out = plant.step(duty, dt);
    const double x = out.string_force.y;
    const double y = (b0 * x + b1 * x1 + b2 * x2 - a1 * y1 - a2 * y2) / a0;
    x2 = x1, x1 = x, y2 = y1, y1 = y;
    if (k < n / 4) continue;  // the start's transient
    const double band = out.band_string_force.y;
    err2 += (band - y) * (band - y);
    var2 += y * y;
    mean += y;
    raw2 += (x - y) * (x - y);
  }
  const double m = n - n / 4;
  const double rms_band = std::sqrt(var2 / m - (mean / m) * (mean / m));
  std::printf("  band RMS %.4g N, filters differ by %.3g N, square wave %.3g N\n", rms_band, std::sqrt(err2 / m),
              std::sqrt(raw2 / m));
  EXPECT_LT(std::sqrt(err2 / m), 1e-4 * rms_band);  // the two discretisations agree (measured: 5e-7)
  EXPECT_GT(std::sqrt(raw2 / m), 0.05 * rms_band);  // and the square wave was there to remove
}

TEST(PlantStatics, ResetHoldsTheBiasTensionAtTheCentre) {
  PlantParams p;
  p.scene.gravity = {};
  Plant plant(p);
  plant.reset(0.7);
  for (int i = 0; i < 8; ++i) {
    EXPECT_NEAR(plant.output().tension[i], 0.7, 1e-12) << i;
    EXPECT_EQ(plant.output().counts[i], 0) << i;
    // The current that holds 0.7 N at standstill, and the duty that drives it (stall equation).
    EXPECT_NEAR(plant.motor_current(i), 0.7 * plant_ref::kRadius / plant_ref::kKt, 1e-15);
  }
  EXPECT_NEAR(plant.holding_duty(0.7) * plant_ref::kSupply / plant_ref::kR, 0.7 * plant_ref::kRadius / plant_ref::kKt,
              1e-12);
  EXPECT_EQ(plant.output().taut, 0xFFu);
  EXPECT_EQ(plant.output().status, Status::ok);
}

// Translation-only grip, finger and gravity on, a different duty on every motor: after the transients the
// tensions are the stall tensions and the grip sits where they, the finger and gravity balance.
TEST(PlantStatics, SettlesToTheStallEquilibriumTranslationOnly) {
  PlantParams p;
  p.scene.translation_only = true;
  p.finger.anchor = {0.004, -0.003, 0.002};
  Plant plant(p);
  plant.reset(0.3);
  const double duty[8] = {0.05, 0.08, 0.11, 0.06, 0.09, 0.04, 0.10, 0.07};
  run(plant, duty, 2.0);
  double expected[8];
  for (int i = 0; i < 8; ++i) {
    expected[i] = plant_ref::stall_tension(duty[i]);
    EXPECT_NEAR(plant.output().tension[i], expected[i], 1e-9) << i;
    EXPECT_NEAR(plant.motor_speed(i), 0.0, 1e-9) << i;
  }
  const V3 x = plant_ref::balance_position(spidar_ref::x3_device(), expected, p.finger.stiffness, v3(p.finger.anchor),
                                           p.grip.mass, v3(p.scene.gravity));
  const V3 got = v3(plant.position());
  std::printf("  settled at (%.6f, %.6f, %.6f) mm, reference (%.6f, %.6f, %.6f) mm\n", got[0] * 1e3, got[1] * 1e3,
              got[2] * 1e3, x[0] * 1e3, x[1] * 1e3, x[2] * 1e3);
  EXPECT_LT(spidar_ref::len3(spidar_ref::sub(got, x)), 1e-10);
  // The finger carries what the strings and gravity leave over.
  const V3 finger = v3(plant.output().finger_force);
  const V3 expected_finger = spidar_ref::scale(p.finger.stiffness, spidar_ref::sub(x, v3(p.finger.anchor)));
  EXPECT_LT(spidar_ref::len3(spidar_ref::sub(finger, expected_finger)), 1e-7);
}

// Full 6-DOF: the grip turns until the string torques balance the finger's torsional spring.
TEST(PlantStatics, SettlesToForceAndTorqueBalanceSixDof) {
  PlantParams p;  // defaults: 6-DOF, finger, gravity
  Plant plant(p);
  plant.reset(0.3);
  const double duty[8] = {0.12, 0.05, 0.07, 0.10, 0.06, 0.11, 0.04, 0.09};
  run(plant, duty, 2.0);
  double tension[8];
  for (int i = 0; i < 8; ++i) {
    tension[i] = plant_ref::stall_tension(duty[i]);
    EXPECT_NEAR(plant.output().tension[i], tension[i], 1e-9) << i;
  }
  const auto q = plant.orientation();
  const spidar_ref::M3 rot = plant_ref::rotation_of(q.w, q.x, q.y, q.z);
  const V3 pos = v3(plant.position());
  const V3 force = plant_ref::static_force(spidar_ref::x3_device(), pos, rot, tension, p.finger.stiffness,
                                           v3(p.finger.anchor), p.grip.mass, v3(p.scene.gravity));
  const spidar_ref::Strings s = spidar_ref::strings_at(spidar_ref::x3_device(), pos, rot);
  V3 torque{};
  for (int i = 0; i < 8; ++i) torque = spidar_ref::add(torque, spidar_ref::scale(tension[i], s.m[i]));
  // Finger torque: torsional spring on the rotation vector, 2·(x, y, z) of the quaternion (small angles).
  const double sign = q.w < 0 ? -2.0 : 2.0;
  torque = spidar_ref::sub(torque, spidar_ref::scale(p.finger.torsional_stiffness * sign, V3{q.x, q.y, q.z}));
  const double angle = spidar_ref::angle_of(rot);
  std::printf("  turned %.3f deg; residual force %.2e N, torque %.2e N·m\n", angle * 360 / kTwoPi,
              spidar_ref::len3(force), spidar_ref::len3(torque));
  EXPECT_GT(angle, 1e-3);  // the unequal tensions do twist the grip: the torque balance is not trivial
  EXPECT_LT(spidar_ref::len3(force), 1e-8);
  EXPECT_LT(spidar_ref::len3(torque), 1e-10);
}

// Without a finger (design §16: no finger model unless asked for) and without gravity the grip floats to
// where the eight stall tensions alone balance.
TEST(PlantStatics, FloatsOnItsStringsWithoutAFinger) {
  PlantParams p;
  p.scene.translation_only = true;
  p.scene.finger = false;
  p.scene.gravity = {};
  Plant plant(p);
  plant.reset(0.3);
  const double duty[8] = {0.07, 0.07, 0.09, 0.09, 0.07, 0.07, 0.05, 0.05};
  run(plant, duty, 6.0);  // the only restoring force is the strings' geometric stiffness, ~40 N/m: slow
  double tension[8];
  for (int i = 0; i < 8; ++i) tension[i] = plant_ref::stall_tension(duty[i]);
  const V3 x = plant_ref::balance_position(spidar_ref::x3_device(), tension, 0.0, V3{}, 0.0, V3{});
  std::printf("  floats at (%.4f, %.4f, %.4f) mm\n", x[0] * 1e3, x[1] * 1e3, x[2] * 1e3);
  EXPECT_GT(spidar_ref::len3(x), 1e-3);  // the unequal pulls do move it off the centre
  EXPECT_LT(spidar_ref::len3(spidar_ref::sub(v3(plant.position()), x)), 1e-9);
  EXPECT_EQ(plant.output().finger_force.x, 0.0);
  EXPECT_LT(hmp::spidar::norm(plant.output().string_force), 1e-9);
}

// Top strings paid out (negative duty): they go slack and must carry exactly nothing, while their motors
// run up to the no-load speed; the bottom strings, finger and gravity balance the grip on their own.
// The switch functions (each string's stretch and spring force) are kept from the last state the
// dynamics computed: asked at another state, after a derivative at one, or after a free length changed,
// they are those of the state asked for, to the bit, as a fresh copy of the dynamics gives them.
TEST(PlantSwitchFunctions, AreThoseOfTheStateAskedFor) {
  PlantParams p;
  Plant plant(p);
  plant.reset(0.3);
  const double duty[8] = {0.1, 0.1, 0.1, 0.1, -0.05, -0.05, -0.05, -0.05};
  run(plant, duty, 0.05);
  PlantDynamics d = plant.dynamics();
  const int n = d.size();
  std::vector<double> y1(plant.state(), plant.state() + n), y2 = y1, rates(static_cast<std::size_t>(n));
  y2[0] += 1e-3;  // the grip 1 mm along x
  auto fresh = [&](const std::vector<double>& y, const PlantDynamics& like) {
    PlantDynamics copy = like;
    PlantForces f;
    copy.evaluate(y.data(), f);
    std::vector<double> g(f.stretch, f.stretch + 8);
    g.insert(g.end(), f.spring, f.spring + 8);
    return g;
  };
  auto asked = [&](const std::vector<double>& y) {
    std::vector<double> g(16);
    EXPECT_EQ(d.switch_functions(y.data(), g.data()), 16);
    return g;
  };
  const std::vector<double> at1 = fresh(y1, d), at2 = fresh(y2, d);
  ASSERT_NE(at1, at2);
  d.derivative(y1.data(), rates.data());
  EXPECT_EQ(asked(y1), at1);
  EXPECT_EQ(asked(y2), at2);
  EXPECT_EQ(asked(y2), at2);
  d.derivative(y1.data(), rates.data());
  EXPECT_EQ(asked(y2), at2);
  d.set_free_length(0, d.free_length(0) - 0.01);  // string 0 stretched 1 cm more at every state
  const std::vector<double> longer = asked(y2);
  EXPECT_EQ(longer, fresh(y2, d));
  EXPECT_DOUBLE_EQ(longer[0], at2[0] + 0.01);
}

// The strings' geometry is kept from the last pose the dynamics computed: a derivative after one at
// another state (the pose moved in position only, in orientation only, or not at all) is, to the bit, the
// one a newly made copy of the dynamics computes.
TEST(PlantDynamicsGeometry, IsThatOfThePoseAsked) {
  PlantParams p;
  Plant plant(p);
  plant.reset(0.3);
  const double duty[8] = {0.2, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.3};
  run(plant, duty, 0.05);
  PlantDynamics d = plant.dynamics();
  for (int i = 0; i < 8; ++i) d.set_voltage(i, 0.0);  // as in a copy made anew
  const int n = d.size();
  const std::vector<double> at(plant.state(), plant.state() + n);
  std::vector<double> moved = at, turned = at, faster = at;
  moved[state::position + 1] += 1e-4;
  turned[state::orientation + 2] += 1e-3;  // not unit any more: normalised by the dynamics
  faster[state::velocity] += 1e-3;
  auto made_anew = [&](const std::vector<double>& y) {
    PlantDynamics fresh(d.params());
    for (int i = 0; i < 8; ++i) fresh.set_free_length(i, d.free_length(i));
    std::vector<double> rates(static_cast<std::size_t>(n));
    fresh.derivative(y.data(), rates.data());
    return rates;
  };
  auto rates_of = [&](const std::vector<double>& y) {
    std::vector<double> rates(static_cast<std::size_t>(n));
    d.derivative(y.data(), rates.data());
    return rates;
  };
  ASSERT_NE(made_anew(moved), made_anew(at));
  ASSERT_NE(made_anew(turned), made_anew(at));
  const std::vector<double>* order[] = {&at, &moved, &at, &turned, &moved, &faster, &at, &turned, &turned};
  for (const std::vector<double>* y : order) EXPECT_EQ(rates_of(*y), made_anew(*y));
}

// Stretch coordinates (PlantDynamics::to_linear), with the grip moved, moving and turning: they map back to
// the state they came from; the stretch is the one the forces are computed from; and their rates are the
// time derivative of the map along the motion, checked by a central difference of to_linear() over ±1 µs
// of the state's own derivative.
TEST(PlantStretchCoordinates, MapBackAndTheirRatesAreTheStretchesDerivative) {
  PlantParams p;
  p.string.stiffness = 1e7;
  Plant plant(p);
  plant.reset(0.5);
  PlantDynamics d = plant.dynamics();
  ASSERT_TRUE(d.has_linear_coordinates());
  const int n = d.size();
  std::vector<double> z(static_cast<std::size_t>(n)), y(plant.state(), plant.state() + n);
  d.to_linear(y.data(), z.data());
  const double v[3] = {0.3, -0.2, 0.1}, w[3] = {2.0, -1.0, 3.0};  // m/s, rad/s
  for (int a = 0; a < 3; ++a) {
    z[static_cast<std::size_t>(state::velocity + a)] = v[a];
    z[static_cast<std::size_t>(state::angular_velocity + a)] = w[a];
  }
  z[state::position] += 0.02;
  z[state::orientation + 1] += 0.1;  // not unit: the dynamics normalise it
  d.from_linear(z.data(), y.data());

  std::vector<double> back(static_cast<std::size_t>(n));
  d.to_linear(y.data(), back.data());
  PlantForces forces;
  d.evaluate(y.data(), forces);
  for (int i = 0; i < n; ++i) EXPECT_NEAR(back[i], z[i], 1e-15 * (1 + std::fabs(z[i]))) << "state " << i;
  for (int i = 0; i < 8; ++i) EXPECT_EQ(back[state::angle + i], forces.stretch[i]) << "string " << i;
  for (int i = 0; i < 8; ++i) EXPECT_NE(y[state::angle + i], plant.state()[state::angle + i]) << "string " << i;

  std::vector<double> f(static_cast<std::size_t>(n)), rates(static_cast<std::size_t>(n));
  d.derivative(y.data(), f.data());
  d.linear_rates(y.data(), f.data(), rates.data());
  const double eps = 1e-6;  // s
  std::vector<double> ahead(y), behind(y), z_ahead(static_cast<std::size_t>(n)), z_behind(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    ahead[i] += eps * f[i];
    behind[i] -= eps * f[i];
  }
  d.to_linear(ahead.data(), z_ahead.data());
  d.to_linear(behind.data(), z_behind.data());
  double worst = 0, fastest = 0;
  for (int i = 0; i < n; ++i) {
    const double difference = (z_ahead[i] - z_behind[i]) / (2 * eps);
    if (i < state::speed) fastest = std::fmax(fastest, std::fabs(rates[i]));
    worst = std::fmax(worst, std::fabs(rates[i] - difference) / (1 + std::fabs(difference)));
    EXPECT_NEAR(rates[i], difference, 1e-7 * (1 + std::fabs(difference))) << "state " << i;
  }
  std::printf("  stretch rates up to %.3f m/s; worst mismatch %.1e of the rate\n", fastest, worst);
  // Below the threshold the exponential integrator keeps the plant's own coordinates.
  PlantParams soft;
  soft.string.stiffness = 1e5;
  EXPECT_FALSE(PlantDynamics(soft).has_linear_coordinates());
}

// The drift from a linearisation's origin: the displacement over the reach, then the rotation; asked
// with a bound, a displacement alone beyond it is answered −1 (the rotation can only add), and one within
// it gives all six components as without a bound.
TEST(PlantDynamicsDrift, StopsOnceTheDisplacementIsBeyondTheBound) {
  PlantParams p;
  Plant plant(p);
  plant.reset(0.3);
  const PlantDynamics& d = plant.dynamics();
  const std::vector<double> origin(plant.state(), plant.state() + d.size());
  std::vector<double> y = origin;
  const double reach = kLinearDrift.distance;  // 10⁴–10⁵ N/m: not scaled
  y[state::position] += 0.6 * reach;
  y[state::orientation + 1] += 0.5 * kLinearDrift.angle / 2;  // a rotation vector of ~0.5 of the reach
  double all[kMaxDrift], bounded[kMaxDrift];
  ASSERT_EQ(d.linearisation_drift(origin.data(), y.data(), all), 6);
  EXPECT_NEAR(all[0], 0.6, 1e-9);
  EXPECT_NEAR(all[3], 0.5, 0.01);
  EXPECT_EQ(d.linearisation_drift(origin.data(), y.data(), bounded, 0.35), -1);  // 0.36 beyond 0.35
  ASSERT_EQ(d.linearisation_drift(origin.data(), y.data(), bounded, 0.37), 6);   // 0.36 + 0.25 is not asked
  for (int i = 0; i < 6; ++i) EXPECT_EQ(bounded[i], all[i]) << i;
}

TEST(PlantStatics, SlackStringsCarryNoForce) {
  PlantParams p;
  p.scene.translation_only = true;
  Plant plant(p);
  plant.reset(0.3);
  const double duty[8] = {0.1, 0.1, 0.1, 0.1, -0.05, -0.05, -0.05, -0.05};
  int slack_ticks = 0;
  for (int k = 0; k < 1500; ++k) {
    const PlantOutput& out = plant.step(duty, 1e-3);
    for (int i = 4; i < 8; ++i)
      if (!(out.taut & (1u << i))) {
        ++slack_ticks;
        ASSERT_EQ(out.tension[i], 0.0) << "string " << i << " tick " << k;
      }
  }
  EXPECT_GT(slack_ticks, 4 * 1400);  // slack within the first 100 ms and from then on
  EXPECT_EQ(plant.output().taut, 0x0Fu);
  double tension[8] = {};
  for (int i = 0; i < 4; ++i) tension[i] = plant_ref::stall_tension(0.1);
  const V3 x = plant_ref::balance_position(spidar_ref::x3_device(), tension, p.finger.stiffness, v3(p.finger.anchor),
                                           p.grip.mass, v3(p.scene.gravity));
  EXPECT_LT(spidar_ref::len3(spidar_ref::sub(v3(plant.position()), x)), 1e-10);
  for (int i = 4; i < 8; ++i) EXPECT_NEAR(plant.motor_speed(i), plant_ref::no_load_speed(-0.05), 1e-6) << i;
  // The net string force is the bottom strings' alone.
  const spidar_ref::Strings s =
      spidar_ref::strings_at(spidar_ref::x3_device(), x, spidar_ref::M3{V3{1, 0, 0}, V3{0, 1, 0}, V3{0, 0, 1}});
  V3 f{};
  for (int i = 0; i < 4; ++i) f = spidar_ref::add(f, spidar_ref::scale(tension[i], s.u[i]));
  EXPECT_LT(spidar_ref::len3(spidar_ref::sub(v3(plant.output().string_force), f)), 1e-8);
}

// The unilateral law at single states: slack with the motor reeling in fast, and barely taut while
// the string is released fast (the damping term would push): both carry nothing.
TEST(PlantStatics, DampingNeverMakesAStringPush) {
  PlantParams p;
  p.scene.translation_only = true;
  Plant plant(p);
  plant.reset(0.3);
  double y[kMaxState];
  for (int i = 0; i < plant.state_size(); ++i) y[i] = plant.state()[i];
  const double k = p.string.stiffness, r = p.motor.drive.pulley_radius;
  // String 0: 1 µm slack, reeling in at 100 rad/s (0.5 m/s of string).
  y[state::angle + 0] = -(0.3 / k + 1e-6) / r;
  y[state::speed + 0] = 100.0;
  // String 1: 1 µm taut, paying out at 10 rad/s: k·s + c·ṡ = 0.01 − 0.1 < 0.
  y[state::angle + 1] = -(0.3 / k - 1e-6) / r;
  y[state::speed + 1] = -10.0;
  plant.set_state(y);
  EXPECT_EQ(plant.output().tension[0], 0.0);
  EXPECT_EQ(plant.output().tension[1], 0.0);
  EXPECT_FALSE(plant.output().taut & 1u);
  EXPECT_TRUE(plant.output().taut & 2u);
  EXPECT_NEAR(plant.output().tension[2], 0.3, 1e-12);
}

TEST(PlantStatics, DutiesSaturateAtPlusMinusOne) {
  PlantParams p;
  p.scene.translation_only = true;
  Plant over(p), full(p), invalid(p), zero(p);
  double d5[8], d1[8], dnan[8], d0[8] = {};
  for (int i = 0; i < 8; ++i) {
    d5[i] = 5.0;
    d1[i] = 1.0;
    dnan[i] = std::numeric_limits<double>::quiet_NaN();
  }
  for (int k = 0; k < 500; ++k) {
    const PlantOutput& a = over.step(d5, 1e-3);
    const PlantOutput& b = full.step(d1, 1e-3);
    const PlantOutput& c = invalid.step(dnan, 1e-3);
    const PlantOutput& z = zero.step(d0, 1e-3);
    ASSERT_TRUE(a.flags & flag::saturated);
    ASSERT_FALSE(b.flags & flag::saturated);
    ASSERT_TRUE(c.flags & flag::invalid_input);
    for (int i = 0; i < 8; ++i) {
      ASSERT_EQ(a.tension[i], b.tension[i]);  // clamped to exactly the same input
      ASSERT_EQ(c.tension[i], z.tension[i]);  // NaN is driven as 0
    }
  }
  // Full duty on every motor: every string at the 12 V stall tension (7.86 N).
  for (int i = 0; i < 8; ++i) EXPECT_NEAR(full.output().tension[i], plant_ref::stall_tension(1.0), 1e-8) << i;
  EXPECT_NEAR(plant_ref::stall_tension(1.0), 7.86, 0.01);
  // Full reverse: every string slack, every motor at its no-load speed (−563 rad/s).
  Plant reverse(p);
  double dm1[8];
  for (double& d : dm1) d = -1.0;
  run(reverse, dm1, 0.5);
  EXPECT_EQ(reverse.output().taut, 0u);
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(reverse.output().tension[i], 0.0);
    EXPECT_NEAR(reverse.motor_speed(i), plant_ref::no_load_speed(-1.0), 1e-6);
  }
  EXPECT_FALSE(reverse.unstable());
}

// 512 lines × 4 = 2048 counts per pulley turn, counting up as string pays out, changing only on an
// edge (floor), wrapping like a 32-bit hardware counter.
TEST(PlantStatics, EncodersCountQuarterLinesAndWrap) {
  PlantParams p;
  p.scene.translation_only = true;
  Plant plant(p);
  double y[kMaxState];
  for (int i = 0; i < plant.state_size(); ++i) y[i] = plant.state()[i];
  const double per_count = kTwoPi / 2048.0;
  const long long mid[8] = {0, 1, 2047, 2048, -1, -2049, 1000000, (1LL << 31) + 5};
  for (int i = 0; i < 8; ++i) y[state::angle + i] = -(static_cast<double>(mid[i]) + 0.5) * per_count;
  plant.set_state(y);
  for (int i = 0; i < 8; ++i)
    EXPECT_EQ(plant.output().counts[i], static_cast<std::int32_t>(static_cast<std::uint32_t>(mid[i] & 0xFFFFFFFFLL)))
        << i;
  // One full turn of paying out is 2048 counts.
  for (int i = 0; i < 8; ++i) y[state::angle + i] = -0.25 * per_count;
  plant.set_state(y);
  for (int i = 0; i < 8; ++i) y[state::angle + i] = -0.25 * per_count - kTwoPi;
  const std::int32_t before = plant.output().counts[0];
  plant.set_state(y);
  EXPECT_EQ(plant.output().counts[0] - before, 2048);

  // Running free at full reverse: the counts follow the angle the motor turned.
  Plant running(p);
  double dm1[8];
  for (double& d : dm1) d = -1.0;
  run(running, dm1, 0.3);
  for (int i = 0; i < 8; ++i) {
    const double expected = std::floor(-running.motor_angle(i) / per_count);
    EXPECT_EQ(running.output().counts[i], static_cast<std::int32_t>(expected));
    EXPECT_GT(expected, 0.2 * 500.0 / per_count);  // > 0.2 s at ≥ 500 rad/s
  }
}

// Near the frame edge the strings are long on one side and short on the other; the grip must still
// balance where the reference says, and the step stay stable.
TEST(PlantStatics, BalancesNearTheFrameEdge) {
  PlantParams p;
  p.scene.translation_only = true;
  const auto& f = p.frame;
  p.finger.anchor =
      f.workspace_axes * Vec3d{0.95 * f.workspace_half.x, -0.95 * f.workspace_half.y, 0.5 * f.workspace_half.z};
  p.finger.stiffness = 1000.0;
  Plant plant(p);
  plant.reset(0.3);
  const double duty[8] = {0.06, 0.06, 0.06, 0.06, 0.06, 0.06, 0.06, 0.06};
  run(plant, duty, 2.0);
  ASSERT_FALSE(plant.unstable());
  double tension[8];
  for (double& t : tension) t = plant_ref::stall_tension(0.06);
  const V3 x = plant_ref::balance_position(spidar_ref::x3_device(), tension, p.finger.stiffness, v3(p.finger.anchor),
                                           p.grip.mass, v3(p.scene.gravity));
  EXPECT_LT(spidar_ref::len3(spidar_ref::sub(v3(plant.position()), x)), 1e-10);
  std::printf("  grip at %.1f mm from the centre\n", spidar_ref::len3(x) * 1e3);
}

}  // namespace
