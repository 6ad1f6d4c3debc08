#pragma once
// The SPIDAR-G6 plant the simulated board drives (design §12): eight DC motors winding elastic strings
// tied to a grip held by a finger. Once per control tick the board calls step() with the eight PWM duties
// and reads the encoder counts back; the string tensions and the force on the finger are what a
// measurement rig would see. Double precision, host only; no allocation after construction.
//
//   Plant plant;                  // X3 frame, RE-max 24 motors, k = 10⁴ N/m, ROS2 at 125 µs sub-steps
//   plant.reset(0.3);             // grip at the calibrated centre, every string at 0.3 N
//   every tick: const PlantOutput& out = plant.step(duties, 1e-3);   // out.counts → firmware
//
// A step that leaves the physically possible (NaN, currents, speeds or velocities far beyond what 12 V
// can produce) marks the plant unstable — an explicit integrator past its stable step — and freezes it at
// the last plausible state until reset().
#include <cstdint>
#include <memory>

#include "boards/sim/plant/dynamics.hpp"
#include "boards/sim/plant/integrators.hpp"
#include "boards/sim/plant/plant_params.hpp"

namespace hmp::sim::plant {

enum class Status : std::uint8_t { ok, unstable };

struct PlantOutput {
  double tension[spidar::kStrings]{};       // N, at the end of the step
  Vec3d string_force{};                     // Σ T_i u_i on the grip, N
  Vec3d string_torque{};                    // Σ T_i m_i, N·m
  Vec3d finger_force{};                     // the grip pushing on the finger, N (zero without a finger model)
  Vec3d finger_torque{};                    // N·m
  Vec3d band_string_force{};                // string_force's part below kBandHz (Scene::band_force only), N
  std::int32_t counts[spidar::kStrings]{};  // encoders: 2048 per pulley turn, growing as string pays out
  std::uint32_t taut = 0;                   // bit i: string i taut
  spidar::Flags flags = 0;                  // this step: saturated (a duty clamped to ±1), invalid_input (NaN duty,
                                            // driven as 0), plus the geometry's short_string / outside_workspace
  Status status = Status::ok;
};

class Plant {
 public:
  explicit Plant(const PlantParams& params = {});

  // Grip at the calibrated centre in its rest orientation, at rest; every string stretched to
  // `bias_tension` with its motor holding it at standstill (current r·T/Kt); encoders at zero; the
  // finger anchor back to its configured place. Clears the unstable state.
  void reset(double bias_tension = 0.3);
  // Duty that holds `tension` at standstill: the stall equation, through shared/spidar's MotorModel.
  double holding_duty(double tension) const;

  // Applies the duties (clamped to ±1; NaN → 0) for dt seconds, in ceil(dt / max_step) equal sub-steps.
  const PlantOutput& step(const double (&duty)[spidar::kStrings], double dt);
  const PlantOutput& step(const float (&duty)[spidar::kStrings], double dt);
  const PlantOutput& output() const { return out_; }
  bool unstable() const { return out_.status == Status::unstable; }
  double time() const { return time_; }

  // The hand: move the finger's anchor (a scene's user moving the grip).
  void set_finger_anchor(const Vec3d& anchor) { dynamics_.set_finger_anchor(anchor); }

  // ---- inspection (tests, benchmarks) ----
  const PlantParams& params() const { return dynamics_.params(); }
  const PlantDynamics& dynamics() const { return dynamics_; }
  const Integrator& integrator() const { return *integrator_; }
  int state_size() const { return dynamics_.size(); }
  const double* state() const { return y_; }
  // Replaces the state (size state_size()) and recomputes the outputs; clears the unstable state.
  void set_state(const double* y);
  Vec3d position() const { return {y_[state::position], y_[state::position + 1], y_[state::position + 2]}; }
  Vec3d velocity() const { return {y_[state::velocity], y_[state::velocity + 1], y_[state::velocity + 2]}; }
  spidar::Quat<double> orientation() const;
  double motor_angle(int i) const { return y_[state::angle + i]; }
  double motor_speed(int i) const { return y_[state::speed + i]; }
  double motor_current(int i) const { return y_[state::current + i]; }

 private:
  bool plausible(const double* y) const;
  void refresh_output();

  PlantDynamics dynamics_;
  std::unique_ptr<Integrator> integrator_;
  double y_[kMaxState]{};
  double saved_[kMaxState]{};
  double time_ = 0;
  PlantOutput out_{};
  double radians_per_count_;
  // Beyond these the state is not something the hardware can reach: the integration has blown up.
  double max_current_, max_speed_;
};

}  // namespace hmp::sim::plant
