#pragma once
// Parameters of the SPIDAR-G6 plant simulator (design §12): motors, strings, grip, finger, and which parts
// of the model a scene needs (design §16). The geometry and the motor's drive constants come from
// shared/spidar (one source of truth for the firmware and the simulator); this file only adds what the
// firmware never needs: inductance, inertias, string elasticity, the hand.
#include "boards/sim/plant/integrators.hpp"
#include "shared/spidar/geometry.hpp"
#include "shared/spidar/motor.hpp"

namespace hmp::sim::plant {

using Vec3d = spidar::Vec3<double>;

struct MotorDynamics {
  spidar::MotorParams<double> drive{};  // Kt (= Ke), R, supply, pulley radius, b, encoder counts/rev
  // Terminal inductance: design §12 gives the electrical time constant L/R ≈ 0.1 ms with R = 6.5 Ω.
  double inductance = 0.65e-3;  // H
  // Rotor + pulley inertia. RE-max 24 rotors are listed at about 1.1 g·cm²; an aluminium pulley of 10 mm
  // diameter and 6 mm length adds ½·(1.27 g)·(5 mm)² ≈ 0.16 g·cm². Seen from the string this is
  // J/r² ≈ 5 g of moving mass per motor, comparable to the grip's share.
  double inertia = 1.25e-7;  // kg·m²
};

struct StringParams {
  // Unilateral spring-damper: T = max(0, k·s + c·ṡ) while the stretch s > 0, else 0. k for ~10 cm of
  // braided polyethylene line is ~10⁴ N/m; 10³–10⁶ covers soft to wire-like strings.
  double stiffness = 1e4;  // N/m
  // ~15% of critical damping against one motor's 5 g at k = 10⁴ N/m (2·√(k·m) ≈ 14 N·s/m).
  double damping = 2.0;  // N·s/m
};

struct GripParams {
  double mass = 0.03;      // kg: a 45 mm plastic ball with its string ties
  double radius = 0.0225;  // m: inertia of a solid ball, ⅖·m·r² (isotropic, so no gyroscopic term)
  double inertia() const { return 0.4 * mass * radius * radius; }
};

// The user's finger(s) holding the grip: a spring-damper from an anchor point (which a scene may move)
// to the grip centre, and a torsional one towards the rest orientation. The torsional terms default to
// the linear ones acting at the grip surface (k·ρ², c·ρ²): a finger pad pressing on the ball.
struct FingerParams {
  double stiffness = 500.0;                              // N/m
  double damping = 2.0;                                  // N·s/m
  double torsional_stiffness = 500.0 * 0.0225 * 0.0225;  // N·m/rad
  double torsional_damping = 2.0 * 0.0225 * 0.0225;      // N·m·s/rad
  Vec3d anchor{};                                        // device frame, m
};

// design §16: the simulator integrates only what the scene asks for.
struct Scene {
  bool translation_only = false;   // grip keeps its rest orientation: 30 states instead of 37
  bool finger = true;              // without it the grip floats on its strings alone
  Vec3d gravity{0.0, -9.81, 0.0};  // device frame is Y up
  // The string force's part below kBandHz, the band a finger feels, carried as 6 more states (see
  // dynamics.hpp): a measurement's option (the work-precision error of that band), off for simulation.
  bool band_force = false;
};

struct StepperParams {
  Method method = Method::exponential;
  // Largest internal step: step(duties, dt) takes ceil(dt / max_step) equal sub-steps; 0: the method's
  // default_max_step() (docs/performance.md, sim-work-precision, measures each).
  double max_step = 0;  // s
  // Linearly implicit methods re-evaluate their Jacobian after this much simulated time (and when a
  // string comes within kJacobianSlackMargin of taut or leaves it); in between they are W-methods with a
  // frozen one. It changes only as the grip moves, a few mm in 8 ms at hand speeds.
  double jacobian_max_age = 8e-3;  // s
  double effective_max_step() const { return max_step > 0 ? max_step : default_max_step(method); }
};

struct PlantParams {
  spidar::Frame<double> frame = spidar::x3_frame<double>();
  MotorDynamics motor{};
  StringParams string{};
  GripParams grip{};
  FingerParams finger{};
  Scene scene{};
  StepperParams stepper{};
};

}  // namespace hmp::sim::plant
