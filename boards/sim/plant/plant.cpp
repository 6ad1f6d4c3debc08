#include "boards/sim/plant/plant.hpp"

#include <cmath>
#include <numbers>

namespace hmp::sim::plant {

using spidar::kStrings;

namespace {
constexpr double kTwoPi = 2 * std::numbers::pi;
// Plausibility limits that are not motor-specific: the frame is ~0.2 m across, a hand moves at ~1 m/s.
constexpr double kMaxDistance = 1.0;         // m from the frame centre
constexpr double kMaxVelocity = 50.0;        // m/s
constexpr double kMaxAngularVelocity = 1e4;  // rad/s
}  // namespace

Plant::Plant(const PlantParams& params)
    : dynamics_(params),
      integrator_(make_integrator(params.stepper.method, IntegratorOptions{params.stepper.jacobian_max_age})) {
  const spidar::MotorParams<double>& d = params.motor.drive;
  radians_per_count_ = kTwoPi / static_cast<double>(d.counts_per_rev);
  // A reversing motor sees at most 2·V_supply across its resistance; at no load it spins at V_supply/Ke.
  // Twenty times those is far outside anything the hardware does, and far below a blow-up's magnitudes.
  max_current_ = 20.0 * 2.0 * d.supply_voltage / d.resistance;
  max_speed_ = 20.0 * d.supply_voltage / d.torque_constant;
  reset();
}

double Plant::holding_duty(double tension) const {
  spidar::Flags ignored = 0;
  return spidar::MotorModel<double>(params().motor.drive).duty(tension, 0.0, ignored);
}

void Plant::reset(double bias_tension) {
  const PlantParams& p = params();
  const spidar::MotorParams<double>& d = p.motor.drive;
  for (double& v : y_) v = 0;
  if (!p.scene.translation_only) y_[state::orientation] = 1.0;  // identity quaternion: the rest orientation
  double rest[kStrings];
  spidar::rest_lengths(p.frame, rest);
  const double tension = bias_tension > 0 ? bias_tension : 0.0;
  for (int i = 0; i < kStrings; ++i) {
    dynamics_.set_free_length(i, rest[i] - tension / p.string.stiffness);
    y_[state::current + i] = d.pulley_radius * tension / d.torque_constant;
    dynamics_.set_voltage(i, d.resistance * y_[state::current + i]);
  }
  dynamics_.set_finger_anchor(p.finger.anchor);
  integrator_->invalidate();
  time_ = 0;
  out_ = {};
  refresh_output();
  dynamics_.set_band_at_rest(y_, out_.string_force);
  out_.band_string_force = dynamics_.band_force(y_);
}

void Plant::set_state(const double* y) {
  for (int i = 0; i < dynamics_.size(); ++i) y_[i] = y[i];
  integrator_->invalidate();
  out_.status = Status::ok;
  refresh_output();
}

spidar::Quat<double> Plant::orientation() const {
  if (params().scene.translation_only) return {};
  const double* q = y_ + state::orientation;
  return {q[0], q[1], q[2], q[3]};
}

const PlantOutput& Plant::step(const float (&duty)[kStrings], double dt) {
  double d[kStrings];
  for (int i = 0; i < kStrings; ++i) d[i] = static_cast<double>(duty[i]);
  return step(d, dt);
}

const PlantOutput& Plant::step(const double (&duty)[kStrings], double dt) {
  spidar::Flags flags = 0;
  const double supply = params().motor.drive.supply_voltage;
  for (int i = 0; i < kStrings; ++i) {
    double d = duty[i];
    if (!std::isfinite(d)) {
      flags |= spidar::flag::invalid_input;
      d = 0;
    } else if (d > 1.0 || d < -1.0) {
      flags |= spidar::flag::saturated;
      d = d > 0 ? 1.0 : -1.0;
    }
    dynamics_.set_voltage(i, d * supply);
  }
  if (out_.status == Status::ok && dt > 0) {
    const double max_step = params().stepper.effective_max_step();
    const double ratio = max_step > 0 ? dt / max_step : 1.0;
    // The 1e-9 keeps dt = n·max_step (up to rounding) at n sub-steps.
    const int substeps = ratio > 1.0 ? static_cast<int>(std::ceil(ratio - 1e-9)) : 1;
    const double h = dt / substeps;
    const int n = dynamics_.size();
    for (int k = 0; k < substeps; ++k) {
      for (int i = 0; i < n; ++i) saved_[i] = y_[i];
      integrator_->step(dynamics_, y_, h);
      if (!plausible(y_)) {
        for (int i = 0; i < n; ++i) y_[i] = saved_[i];
        out_.status = Status::unstable;
        break;
      }
    }
  }
  if (dt > 0) time_ += dt;
  refresh_output();
  out_.flags |= flags;
  return out_;
}

bool Plant::plausible(const double* y) const {
  for (int i = 0; i < dynamics_.size(); ++i)
    if (!std::isfinite(y[i])) return false;
  for (int i = 0; i < kStrings; ++i)
    if (std::fabs(y[state::current + i]) > max_current_ || std::fabs(y[state::speed + i]) > max_speed_) return false;
  const Vec3d x{y[state::position], y[state::position + 1], y[state::position + 2]};
  const Vec3d v{y[state::velocity], y[state::velocity + 1], y[state::velocity + 2]};
  if (spidar::norm(x) > kMaxDistance || spidar::norm(v) > kMaxVelocity) return false;
  if (!params().scene.translation_only) {
    const double* w = y + state::angular_velocity;
    if (w[0] * w[0] + w[1] * w[1] + w[2] * w[2] > kMaxAngularVelocity * kMaxAngularVelocity) return false;
  }
  return true;
}

void Plant::refresh_output() {
  PlantForces f;
  dynamics_.evaluate(y_, f);
  for (int i = 0; i < kStrings; ++i) {
    out_.tension[i] = f.tension[i];
    // Counts grow as string pays out (θ decreases). floor(): a real counter changes only on an edge.
    const double turns = std::floor(-y_[state::angle + i] / radians_per_count_);
    const auto wide = static_cast<std::int64_t>(turns);
    out_.counts[i] = static_cast<std::int32_t>(static_cast<std::uint32_t>(static_cast<std::uint64_t>(wide)));
  }
  out_.string_force = f.string_force;
  out_.string_torque = f.string_torque;
  out_.finger_force = f.finger_force;
  out_.finger_torque = f.finger_torque;
  out_.band_string_force = dynamics_.band_force(y_);
  out_.taut = f.taut;
  out_.flags = f.geometry_flags;
}

}  // namespace hmp::sim::plant
