#include "boards/sim/plant/dynamics.hpp"

#include <cmath>
#include <cstring>

namespace hmp::sim::plant {

using spidar::kStrings;

namespace {

spidar::Quat<double> unit_quaternion(const double* q) {
  const double n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
  const double inv = n2 > 0 ? 1.0 / std::sqrt(n2) : 0.0;
  if (!(inv > 0)) return {};  // zero or NaN: fall back to the rest orientation (the check flags NaN states)
  return {q[0] * inv, q[1] * inv, q[2] * inv, q[3] * inv};
}

constexpr double kSqrt2 = 1.41421356237309504880;

Vec3d load3(const double* p) { return {p[0], p[1], p[2]}; }
void store3(double* p, const Vec3d& v) {
  p[0] = v.x;
  p[1] = v.y;
  p[2] = v.z;
}

// q' = ½ (0, w) ⊗ q for an angular velocity w in the device frame.
void quaternion_rate(const double* q, const double* w, double* dq) {
  dq[0] = -0.5 * (w[0] * q[1] + w[1] * q[2] + w[2] * q[3]);
  dq[1] = 0.5 * (w[0] * q[0] + w[1] * q[3] - w[2] * q[2]);
  dq[2] = 0.5 * (-w[0] * q[3] + w[1] * q[0] + w[2] * q[1]);
  dq[3] = 0.5 * (w[0] * q[2] - w[1] * q[1] + w[2] * q[0]);
}

// String i's stretch s_i = ℓ_i − (free length − r·θ_i) and its rate ṡ_i = r·ω_i − u_i·v − m_i·w.
double stretch_of(const spidar::StringGeometry<double>& g, int i, double free_length, double r, const double* y) {
  return g.length[i] - (free_length - r * y[state::angle + i]);
}
double stretch_rate_of(const spidar::StringGeometry<double>& g, int i, double r, const double* y, const Vec3d& v,
                       const Vec3d& w) {
  return r * y[state::speed + i] - dot(g.u[i], v) - dot(g.m[i], w);
}

}  // namespace

PlantDynamics::PlantDynamics(const PlantParams& params)
    : params_(params),
      size_((params.scene.translation_only ? state::translation_size : state::full_size) +
            (params.scene.band_force ? state::band_size : 0)),
      band_(params.scene.band_force ? size_ - state::band_size : size_),
      anchor_(params.finger.anchor),
      inv_inductance_(1.0 / params.motor.inductance),
      inv_inertia_(1.0 / params.motor.inertia),
      inv_mass_(1.0 / params.grip.mass),
      inv_grip_inertia_(1.0 / params.grip.inertia()),
      stretch_coordinates_(params.string.stiffness >= kStretchCoordinatesFrom),
      drift_scale_(
          std::sqrt(std::fmin(1.0, params.string.stiffness / kLinearDrift.soft) *
                    (stretch_coordinates_ ? 1.0 : std::fmax(1.0, params.string.stiffness / kLinearDrift.stiff)))),
      switch_frequency_(
          std::sqrt(params.string.stiffness *
                    (params.motor.drive.pulley_radius * params.motor.drive.pulley_radius * inv_inertia_ +
                     kStrings * (inv_mass_ + (params.scene.translation_only
                                                  ? 0.0
                                                  : params.grip.radius * params.grip.radius * inv_grip_inertia_))))) {}

void PlantDynamics::evaluate(const double* y, PlantForces& out, bool bilateral) const {
  compute(y, out, bilateral ? TensionRule::near_bilateral : TensionRule::unilateral, 0);
}

void PlantDynamics::compute(const double* y, PlantForces& out, TensionRule rule, std::uint32_t piece) const {
  const bool full = !params_.scene.translation_only;
  const Vec3d x = load3(y + state::position);
  const Vec3d v = load3(y + state::velocity);
  const Vec3d w = full ? load3(y + state::angular_velocity) : Vec3d{};
  const spidar::StringGeometry<double>& g = strings_at(y);
  const spidar::Quat<double> q = geometry_orientation_;

  const double r = params_.motor.drive.pulley_radius;
  const double k = params_.string.stiffness, c = params_.string.damping;
  out.string_force = {};
  out.string_torque = {};
  out.taut = 0;
  out.near_taut = 0;
  for (int i = 0; i < kStrings; ++i) {
    const double s = stretch_of(g, i, free_length_[i], r, y);
    out.stretch[i] = s;
    const bool near = s > -kJacobianSlackMargin;
    const double rate = stretch_rate_of(g, i, r, y, v, w);
    const double spring = k * s + c * rate;
    out.spring[i] = spring;
    double t = 0;
    switch (rule) {
      case TensionRule::unilateral: t = s > 0 && spring > 0 ? spring : 0.0; break;  // damping cannot push
      case TensionRule::near_bilateral: t = s > 0 || near ? spring : 0.0; break;
      case TensionRule::piece: t = piece & (1u << i) ? spring : 0.0; break;
    }
    if (s > 0) out.taut |= 1u << i;
    if (near) out.near_taut |= 1u << i;
    out.tension[i] = t;
    out.string_force += t * g.u[i];
    out.string_torque += t * g.m[i];
  }
  out.geometry_flags = g.flags;
  std::memcpy(switches_state_, y, sizeof(double) * static_cast<std::size_t>(size_));
  std::memcpy(switches_, out.stretch, sizeof out.stretch);
  std::memcpy(switches_ + kStrings, out.spring, sizeof out.spring);
  switches_valid_ = true;

  if (params_.scene.finger) {
    const FingerParams& f = params_.finger;
    out.finger_force = f.stiffness * (x - anchor_) + f.damping * v;
    // Rotation vector of q for small angles: 2·(x, y, z), the sign chosen so that w ≥ 0 (q and −q agree).
    const double sign = q.w < 0 ? -2.0 : 2.0;
    const Vec3d phi{sign * q.x, sign * q.y, sign * q.z};
    out.finger_torque = full ? f.torsional_stiffness * phi + f.torsional_damping * w : Vec3d{};
  } else {
    out.finger_force = {};
    out.finger_torque = {};
  }
}

const spidar::StringGeometry<double>& PlantDynamics::strings_at(const double* y) const {
  const bool full = !params_.scene.translation_only;
  // The strings' geometry depends on the pose only: a Jacobian's columns for the motors and the
  // velocities (30 of 37) and a state differentiated twice find it as it was.
  // The pose, position and orientation (not adjacent in the state), compared bit for bit.
  constexpr std::size_t kPositionBytes = sizeof(double) * 3, kOrientationBytes = sizeof(double) * 4;
  const bool same_pose = geometry_valid_ && std::memcmp(geometry_pose_, y + state::position, kPositionBytes) == 0 &&
                         (!full || std::memcmp(geometry_pose_ + 3, y + state::orientation, kOrientationBytes) == 0);
  if (!same_pose) {
    std::memcpy(geometry_pose_, y + state::position, kPositionBytes);
    if (full) std::memcpy(geometry_pose_ + 3, y + state::orientation, kOrientationBytes);
    geometry_orientation_ = full ? unit_quaternion(y + state::orientation) : spidar::Quat<double>{};
    const spidar::Mat3<double> rotation = spidar::to_matrix(geometry_orientation_);
    spidar::compute_strings(params_.frame, load3(y + state::position), rotation, geometry_);
    geometry_valid_ = true;
  }
  return geometry_;
}

void PlantDynamics::to_linear(const double* y, double* z) const {
  std::memcpy(z, y, sizeof(double) * static_cast<std::size_t>(size_));
  const spidar::StringGeometry<double>& g = strings_at(y);
  const double r = params_.motor.drive.pulley_radius;
  for (int i = 0; i < kStrings; ++i) z[state::angle + i] = stretch_of(g, i, free_length_[i], r, y);
}

void PlantDynamics::from_linear(const double* z, double* y) const {
  std::memcpy(y, z, sizeof(double) * static_cast<std::size_t>(size_));
  const spidar::StringGeometry<double>& g = strings_at(z);
  const double inv_r = 1.0 / params_.motor.drive.pulley_radius;
  for (int i = 0; i < kStrings; ++i)
    y[state::angle + i] = (z[state::angle + i] - g.length[i] + free_length_[i]) * inv_r;
}

// The stretches' rates are those the tensions' damping reads; every other state's rate is its own.
void PlantDynamics::linear_rates(const double* y, const double* dydt, double* dzdt) const {
  if (dzdt != dydt) std::memcpy(dzdt, dydt, sizeof(double) * static_cast<std::size_t>(size_));
  const spidar::StringGeometry<double>& g = strings_at(y);
  const Vec3d v = load3(y + state::velocity);
  const Vec3d w = params_.scene.translation_only ? Vec3d{} : load3(y + state::angular_velocity);
  const double r = params_.motor.drive.pulley_radius;
  for (int i = 0; i < kStrings; ++i) dzdt[state::angle + i] = stretch_rate_of(g, i, r, y, v, w);
}

double PlantDynamics::linear_scale(int index) const {
  if (index < state::speed) return params_.motor.drive.pulley_radius * scale(index);  // m
  return scale(index);
}

void PlantDynamics::derivative(const double* y, double* dydt) {
  rates(y, dydt, TensionRule::unilateral, 0, &near_taut_);
}

void PlantDynamics::smooth_derivative(const double* y, double* dydt) {
  rates(y, dydt, TensionRule::near_bilateral, 0, nullptr);
}

void PlantDynamics::piece_derivative(const double* y, std::uint32_t piece, double* dydt) {
  rates(y, dydt, TensionRule::piece, piece, nullptr);
}

int PlantDynamics::switch_functions(const double* y, double* g) const {
  if (!switches_valid_ || std::memcmp(switches_state_, y, sizeof(double) * static_cast<std::size_t>(size_)) != 0) {
    PlantForces f;
    compute(y, f, TensionRule::unilateral, 0);
  }
  std::memcpy(g, switches_, sizeof switches_);
  return 2 * kStrings;
}

std::uint32_t PlantDynamics::piece_of(const double* g) const {
  std::uint32_t piece = 0;
  for (int i = 0; i < kStrings; ++i)
    if (g[i] > 0 && g[kStrings + i] > 0) piece |= 1u << i;
  return piece;
}

int PlantDynamics::linearisation_drift(const double* origin, const double* y, double* drift, double beyond) const {
  const double reach = kLinearDrift.distance / drift_scale_;
  double d2 = 0;
  for (int i = 0; i < 3; ++i) {
    drift[i] = (y[state::position + i] - origin[state::position + i]) / reach;
    d2 += drift[i] * drift[i];
  }
  if (params_.scene.translation_only) return 3;
  if (d2 > beyond) return -1;  // the rotation cannot bring it nearer
  // The rotation from origin to y, 2·vec(conj(q_o) ⊗ q) (small angles; the sign chosen so that the scalar
  // part is positive: q and −q are one orientation).
  const spidar::Quat<double> a = unit_quaternion(origin + state::orientation);
  const spidar::Quat<double> a_conj{a.w, -a.x, -a.y, -a.z};
  const spidar::Quat<double> r = a_conj * unit_quaternion(y + state::orientation);
  const double scale = (r.w < 0 ? -2.0 : 2.0) * drift_scale_ / kLinearDrift.angle;
  drift[3] = scale * r.x;
  drift[4] = scale * r.y;
  drift[5] = scale * r.z;
  return 6;
}

void PlantDynamics::rates(const double* y, double* dydt, TensionRule rule, std::uint32_t piece,
                          std::uint32_t* near_taut) const {
  PlantForces f;
  compute(y, f, rule, piece);
  if (near_taut) *near_taut = f.near_taut;
  const MotorDynamics& m = params_.motor;
  const double kt = m.drive.torque_constant, b = m.drive.viscous_friction, r = m.drive.pulley_radius;
  const double resistance = m.drive.resistance;
  for (int i = 0; i < kStrings; ++i) {
    const double omega = y[state::speed + i], current = y[state::current + i];
    dydt[state::angle + i] = omega;
    dydt[state::speed + i] = (kt * current - r * f.tension[i] - b * omega) * inv_inertia_;
    dydt[state::current + i] = (voltage_[i] - resistance * current - kt * omega) * inv_inductance_;
  }
  store3(dydt + state::position, load3(y + state::velocity));
  const Vec3d accel = inv_mass_ * (f.string_force - f.finger_force) + params_.scene.gravity;
  store3(dydt + state::velocity, accel);
  if (!params_.scene.translation_only) {
    quaternion_rate(y + state::orientation, y + state::angular_velocity, dydt + state::orientation);
    store3(dydt + state::angular_velocity, inv_grip_inertia_ * (f.string_torque - f.finger_torque));
  }
  if (band_ < size_) {
    const double w = kBandOmega;
    const double force[3] = {f.string_force.x, f.string_force.y, f.string_force.z};
    for (int a = 0; a < 3; ++a) {
      const double band = y[band_ + 2 * a], rate = y[band_ + 2 * a + 1];
      dydt[band_ + 2 * a] = rate;
      dydt[band_ + 2 * a + 1] = w * w * (force[a] - band) - kSqrt2 * w * rate;  // Butterworth: ζ = 1/√2
    }
  }
}

Vec3d PlantDynamics::band_force(const double* y) const {
  if (band_ == size_) return {};
  return {y[band_], y[band_ + 2], y[band_ + 4]};
}

void PlantDynamics::set_band_at_rest(double* y, const Vec3d& f) const {
  if (band_ == size_) return;
  const double force[3] = {f.x, f.y, f.z};
  for (int a = 0; a < 3; ++a) {
    y[band_ + 2 * a] = force[a];
    y[band_ + 2 * a + 1] = 0;
  }
}

void PlantDynamics::position_rates(const double* y, double* dydt) const {
  for (int i = band_; i < size_; i += 2) dydt[i] = y[i + 1];
  for (int i = 0; i < kStrings; ++i) dydt[state::angle + i] = y[state::speed + i];
  store3(dydt + state::position, load3(y + state::velocity));
  if (!params_.scene.translation_only)
    quaternion_rate(y + state::orientation, y + state::angular_velocity, dydt + state::orientation);
}

bool PlantDynamics::is_position(int index) const {
  if (index >= band_) return (index - band_) % 2 == 0;  // b is the position of its pair (b, b')
  return index < state::speed || (index >= state::position && index < state::velocity) ||
         (index >= state::orientation && index < state::angular_velocity);
}

double PlantDynamics::scale(int index) const {
  if (index >= band_) return (index - band_) % 2 == 0 ? 1.0 : kBandOmega;  // N, N/s
  if (index < state::speed) return 1.0;                                    // rad
  if (index < state::current) return 1.0;                                  // rad/s
  if (index < state::position) return 0.01;                                // A
  if (index < state::orientation) return 0.01;                             // m, m/s
  return 1.0;                                                              // quaternion, rad/s
}

void PlantDynamics::project(double* y) const {
  if (params_.scene.translation_only) return;
  for (int i = 0; i < 4; ++i)
    if (!std::isfinite(y[state::orientation + i])) return;  // leave NaN visible to the stability check
  const spidar::Quat<double> q = unit_quaternion(y + state::orientation);
  y[state::orientation + 0] = q.w;
  y[state::orientation + 1] = q.x;
  y[state::orientation + 2] = q.y;
  y[state::orientation + 3] = q.z;
}

}  // namespace hmp::sim::plant
