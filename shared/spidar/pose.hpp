#pragma once
// Grip pose from the 8 string lengths (design §11): damped Gauss–Newton, warm-started from the previous
// tick's pose, a fixed number of iterations per tick (2 by default):
//
//   (AᵀA + σI) Δ = Aᵀ (L_model − L_measured),   A's row i = [u_iᵀ  m_iᵀ/ρ],
//   position += Δ[0..2],   orientation ← rotation(Δ[3..5]/ρ) · orientation.
//
// Row i is −∂L_i/∂(position, small rotation): moving the grip by δx shortens string i by u_i·δx, turning it
// by δθ shortens it by m_i·δθ. The rotation unknowns are taken as arc lengths ρ·δθ at the grip radius ρ, so
// both blocks of AᵀA are of order 1 and one σ means the same for both; with plain angles the rotation block
// is only ~ρ² ≈ 5e-4, σ = 0.001 would dominate it and the orientation would converge by ~13% per iteration
// (measured: still 0.026 rad off after 12 ticks from a 29° start, 0.013 rad lag while tracking).
// σ then only guards against a singular AᵀA (strings nearly coplanar).
// Lengths come from encoder counts through a calibration taken with the grip at the centre.
#include <cstdint>

#include "shared/spidar/geometry.hpp"

namespace hmp::spidar {

template <class T>
struct PoseParams {
  T sigma = static_cast<T>(0.001);            // Levenberg–Marquardt damping added to AᵀA's diagonal
  int iterations = 2;                         // Gauss–Newton steps per tick
  T rotation_scale = static_cast<T>(0.0225);  // ρ (m): the X3 grip's attachment radius
  // The estimate never turns further than this from the rest orientation (the grip cannot: the strings
  // would wrap); stored as cos of half the angle so the test needs no trigonometry. Default 90°.
  T cos_half_max_angle = static_cast<T>(0.70710678118654752440);
  // The centre stays inside the workspace box grown by this margin on every side.
  T position_margin = static_cast<T>(0.0225);
};

// Encoder counts → string lengths. Counts grow as string pays out (the board flips signs per motor);
// differences are taken in 32-bit wrap-around arithmetic, so counters may roll over.
template <class T>
struct LengthCalibration {
  std::int32_t count_at_rest[kStrings]{};
  T length_at_rest[kStrings]{};
  T length_per_count = 0;

  // The grip is held at the centre in its rest orientation: these counts mean the geometric rest lengths.
  void calibrate(const Frame<T>& frame, const std::int32_t (&counts)[kStrings], T metres_per_count);
  void lengths(const std::int32_t (&counts)[kStrings], T (&out)[kStrings]) const;
};

template <class T>
class PoseEstimator {
 public:
  // Starts (or restarts) from the rest pose: centre, rest orientation — where calibration holds the grip.
  void reset(const Pose<T>& start = {});

  // One tick: params.iterations Gauss–Newton steps towards `lengths` (metres). Non-finite lengths leave the
  // pose unchanged (invalid_input). Returns the flags of the strings at the last linearisation point plus
  // pose_limited / ill_conditioned / invalid_input.
  Flags update(const Frame<T>& frame, const T (&lengths)[kStrings], const PoseParams<T>& params);

  const Pose<T>& pose() const { return pose_; }
  // Strings at the last linearisation point, i.e. one Gauss–Newton step behind pose() (the step is tiny
  // while tracking); the tension solver uses these instead of paying for another evaluation.
  const StringGeometry<T>& strings() const { return strings_; }
  // RMS of L_model − L_measured at the last linearisation point (m): a fit-quality indicator.
  T residual_rms() const { return residual_rms_; }

 private:
  Pose<T> pose_{};
  StringGeometry<T> strings_{};
  T residual_rms_ = 0;
};

}  // namespace hmp::spidar
