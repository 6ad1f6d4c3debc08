#include "shared/spidar/pose.hpp"

#include <cmath>
#include <limits>

#include "shared/spidar/cholesky.hpp"

namespace hmp::spidar {

template <class T>
void LengthCalibration<T>::calibrate(const Frame<T>& frame, const std::int32_t (&counts)[kStrings],
                                     T metres_per_count) {
  rest_lengths(frame, length_at_rest);
  for (int i = 0; i < kStrings; ++i) count_at_rest[i] = counts[i];
  length_per_count = metres_per_count;
}

template <class T>
void LengthCalibration<T>::lengths(const std::int32_t (&counts)[kStrings], T (&out)[kStrings]) const {
  for (int i = 0; i < kStrings; ++i) {
    // Unsigned subtraction wraps like the hardware counter; the result reinterpreted as signed is the travel.
    const auto travel =
        static_cast<std::int32_t>(static_cast<std::uint32_t>(counts[i]) - static_cast<std::uint32_t>(count_at_rest[i]));
    out[i] = length_at_rest[i] + static_cast<T>(travel) * length_per_count;
  }
}

template <class T>
void PoseEstimator<T>::reset(const Pose<T>& start) {
  pose_ = start;
  strings_ = {};
  residual_rms_ = 0;
}

namespace {

// Keeps w ≥ 0 (q and −q are the same rotation; w = cos(angle/2) then measures the angle) and the rotation
// within the limit. Returns true if it had to clamp.
template <class T>
bool limit_rotation(Quat<T>& q, T cos_half_max) {
  if (q.w < 0) q = {-q.w, -q.x, -q.y, -q.z};
  if (q.w >= cos_half_max) return false;
  const T v2 = q.x * q.x + q.y * q.y + q.z * q.z;
  const T scale = v2 > 0 ? std::sqrt((1 - cos_half_max * cos_half_max) / v2) : static_cast<T>(0);
  q = {cos_half_max, q.x * scale, q.y * scale, q.z * scale};
  return true;
}

template <class T>
bool clamp_abs(T& v, T limit) {
  if (v > limit) {
    v = limit;
    return true;
  }
  if (v < -limit) {
    v = -limit;
    return true;
  }
  return false;
}

template <class T>
bool limit_position(Vec3<T>& p, const Frame<T>& frame, T margin) {
  Vec3<T> local = frame.workspace_axes.transposed_times(p);
  bool clamped = clamp_abs(local.x, frame.workspace_half.x + margin);
  clamped |= clamp_abs(local.y, frame.workspace_half.y + margin);
  clamped |= clamp_abs(local.z, frame.workspace_half.z + margin);
  if (clamped) p = frame.workspace_axes * local;
  return clamped;
}

}  // namespace

template <class T>
Flags PoseEstimator<T>::update(const Frame<T>& frame, const T (&lengths)[kStrings], const PoseParams<T>& params) {
  for (int i = 0; i < kStrings; ++i)
    if (!std::isfinite(lengths[i])) return static_cast<Flags>(strings_.flags | flag::invalid_input);
  Flags flags = 0;
  const T inv_rho = static_cast<T>(1) / params.rotation_scale;
  for (int it = 0; it < params.iterations; ++it) {
    compute_strings(frame, pose_.position, to_matrix(pose_.orientation), strings_);
    // Normal equations, lower triangle only.
    T n[6][6] = {};
    T rhs[6] = {};
    T squares = 0;
    for (int i = 0; i < kStrings; ++i) {
      const T e = strings_.length[i] - lengths[i];
      squares += e * e;
      const T a[6] = {strings_.u[i].x, strings_.u[i].y, strings_.u[i].z,
                      strings_.m[i].x, strings_.m[i].y, strings_.m[i].z};
      for (int r = 0; r < 6; ++r) {
        rhs[r] += a[r] * e;
        for (int c = 0; c <= r; ++c) n[r][c] += a[r] * a[c];
      }
    }
    residual_rms_ = std::sqrt(squares * static_cast<T>(1.0 / kStrings));
    // Rotation unknowns as arc lengths ρ·θ: scale the rotation rows/columns by 1/ρ.
    for (int r = 3; r < 6; ++r) {
      rhs[r] *= inv_rho;
      for (int c = 0; c < 3; ++c) n[r][c] *= inv_rho;
      for (int c = 3; c <= r; ++c) n[r][c] *= inv_rho * inv_rho;
    }
    T diag_max = 0;
    for (int r = 0; r < 6; ++r) {
      n[r][r] += params.sigma;
      diag_max = n[r][r] > diag_max ? n[r][r] : diag_max;
    }
    if (!cholesky_factor(n, static_cast<T>(64) * std::numeric_limits<T>::epsilon() * diag_max)) {
      flags |= flag::ill_conditioned;
      break;
    }
    cholesky_solve(n, rhs);
    pose_.position += Vec3<T>{rhs[0], rhs[1], rhs[2]};
    // Small-angle quaternion (1, δ/2) then renormalise: exact to first order, and Gauss–Newton converges to
    // the same fixed point (δ → 0) without any trigonometry.
    const T half = static_cast<T>(0.5) * inv_rho;
    Quat<T> q = Quat<T>{1, half * rhs[3], half * rhs[4], half * rhs[5]} * pose_.orientation;
    const T inv = static_cast<T>(1) / std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    pose_.orientation = {q.w * inv, q.x * inv, q.y * inv, q.z * inv};
    const bool turned = limit_rotation(pose_.orientation, params.cos_half_max_angle);
    const bool moved = limit_position(pose_.position, frame, params.position_margin);
    if (turned || moved) flags |= flag::pose_limited;
  }
  return static_cast<Flags>(flags | strings_.flags);
}

template struct LengthCalibration<float>;
template struct LengthCalibration<double>;
template class PoseEstimator<float>;
template class PoseEstimator<double>;

}  // namespace hmp::spidar
