#pragma once
// Force/torque → string tensions (SPEC §11): the box-constrained quadratic programme
//
//   minimise  λt·|F − Σ t_i u_i|² + λr·|N − Σ t_i m_i|² + s·|t|²   subject to  t_min ≤ t_i ≤ t_max,
//
// equivalently ½ tᵀH t − gᵀt with H = λt UᵀU + λr MᵀM + s I and g = λt UᵀF + λr MᵀN (the objective is twice
// that plus a constant); U and M have the columns u_i and m_i.
// Solved exactly by block principal pivoting (a primal–dual active-set method): guess which strings sit at
// t_min, at t_max or in between, solve the free strings' equations by Cholesky, move every string that
// violates a bound or has a wrong-signed multiplier, repeat. The active set of the previous tick is the
// first guess, so a tick usually needs one solve. docs/spidar.md explains the choice and the measurements.
#include <cstdint>

#include "shared/spidar/geometry.hpp"

namespace hmp::spidar {

template <class T>
struct TensionParams {
  T t_min = static_cast<T>(0.3);  // N: every string stays taut
  T t_max = static_cast<T>(6.0);  // N
  T lambda_t = static_cast<T>(1.0);  // weight of the force error, 1/N²
  // Weight of the torque error, 1/(N·m)². Torques at a 22.5 mm grip are ~45× smaller than the forces that
  // make them, so λr = 40 makes a torque error of G·f cost about 1/50 of a force error f: the force is
  // what the user must feel, and a stray torque of that size is secondary (see docs/spidar.md).
  T lambda_r = static_cast<T>(40.0);
  // s: keeps H positive definite (8 tensions, 6 wrench components: UᵀU + MᵀM has a 2-D null space of
  // internal tension modes) and picks, among wrench-equivalent tension sets, the one with the smallest and
  // most even tensions. Small enough that the wrench error it causes is ≈ s·t/λ ≈ 1 mN.
  T regulariser = static_cast<T>(1e-3);
  // Block-pivoting iterations (each one ≤ 8×8 Cholesky); then projected Gauss–Seidel sweeps as a fallback.
  int max_iterations = 8;
  int fallback_sweeps = 16;
  T degenerate_ratio = static_cast<T>(1e-3);  // conditioning_flags() threshold
};

// Warm start: which strings were at t_min / t_max after the last solve (bit i = string i).
struct TensionState {
  std::uint8_t at_lower = 0;
  std::uint8_t at_upper = 0;
};

template <class T>
struct TensionResult {
  T tension[kStrings]{};  // always within [t_min, t_max], never NaN
  Vec3<T> force{};        // Σ t_i u_i actually produced
  Vec3<T> torque{};       // Σ t_i m_i actually produced
  Flags flags = 0;        // from the geometry + invalid_input, degenerate_geometry, ill_conditioned, not_converged
  std::uint8_t iterations = 0;  // Cholesky solves used
};

// Non-finite F, N, geometry or parameters → every tension at t_min (0 if t_min itself is unusable), the
// state reset and invalid_input set. `state` is read as the first guess and updated.
template <class T>
TensionResult<T> solve_tensions(const StringGeometry<T>& strings, const Vec3<T>& force, const Vec3<T>& torque,
                                const TensionParams<T>& params, TensionState& state);

}  // namespace hmp::spidar
