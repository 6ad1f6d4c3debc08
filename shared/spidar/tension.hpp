#pragma once
// Force/torque → string tensions (design §11): the box-constrained quadratic programme
//
//   minimise  λt·|F − Σ t_i u_i|² + λr·|N − Σ t_i m_i|² + s·|t|²   subject to  t_min ≤ t_i ≤ t_max,
//
// equivalently ½ tᵀH t − gᵀt with H = λt UᵀU + λr MᵀM + s I and g = λt UᵀF + λr MᵀN (the objective is twice
// that plus a constant); U and M have the columns u_i and m_i.
// Solved exactly by an active-set method: guess which strings sit at t_min or t_max (the warm start), solve
// the other strings' equations by Cholesky and check optimality — on most ticks that is all. Otherwise the
// dual active-set method of Goldfarb & Idnani, on a swept copy of H where each active-set change costs one
// 8×8 rank-1 update, finds the right set, and a final Cholesky solve gives the answer. The number of
// changes per solve is capped; docs/spidar.md explains the choice and the measurements.
#include <cstdint>

#include "shared/spidar/geometry.hpp"

namespace hmp::spidar {

template <class T>
struct TensionParams {
  T t_min = static_cast<T>(0.3);     // N: every string stays taut
  T t_max = static_cast<T>(6.0);     // N
  T lambda_t = static_cast<T>(1.0);  // weight of the force error, 1/N²
  // Weight of the torque error, 1/(N·m)². Torques at a 22.5 mm grip are ~45× smaller than the forces that
  // make them, so λr = 40 makes a torque error of G·f cost about 1/50 of a force error f: the force is
  // what the user must feel, and a stray torque of that size is secondary (see docs/spidar.md).
  T lambda_r = static_cast<T>(40.0);
  // s: keeps H positive definite (8 tensions, 6 wrench components: UᵀU + MᵀM has a 2-D null space of
  // internal tension modes) and picks, among wrench-equivalent tension sets, the one with the smallest and
  // most even tensions. Small enough that the wrench error it causes is ≈ s·t/λ ≈ 1 mN.
  T regulariser = static_cast<T>(1e-3);
  // Active-set changes allowed per solve (each ≈ 350 Cortex-M4 instructions, plus ≈ 3,150 once for any
  // change at all). With TensionStateBank warm starts 0.02% of vibration ticks need more than 4 (≤ 2.6 mN
  // off then); a cold start with a large force may need up to 14. Over budget the answer is polished by
  // `fallback_sweeps` projected Gauss–Seidel sweeps (≈ 300 instructions each), flagged not_converged, and
  // the next solve carries on from the active set reached. docs/spidar.md has the trade-off table.
  int max_iterations = 4;
  int fallback_sweeps = 2;
  T degenerate_ratio = static_cast<T>(1e-3);  // conditioning_flags() threshold
};

// Warm start: which strings were at t_min / t_max after the last solve (bit i = string i).
struct TensionState {
  std::uint8_t at_lower = 0;
  std::uint8_t at_upper = 0;
};

// Warm starts for a force that swings back and forth (a vibration): the active set follows the force, so
// the previous tick — half a period away — is a poor first guess. This bank remembers the last active set
// for each of 16 slices of a signed scalar (the force along the vibration direction, over its full scale),
// which makes the first guess right on ~93% of ticks instead of ~64% (docs/spidar.md).
// A slot used for the first time starts from the slot used last, not from scratch (a cold start costs
// several active-set changes).
struct TensionStateBank {
  static constexpr int kSlots = 16;
  TensionState slot[kSlots];
  std::uint16_t used = 0;
  int last = 0;

  // `x` is expected in [−1, 1]; outside (or NaN) it maps to the end slots.
  TensionState& at(float x) {
    const float pos = (x + 1.0f) * (0.5f * static_cast<float>(kSlots));
    const int i = pos >= 0.0f ? (pos < static_cast<float>(kSlots) ? static_cast<int>(pos) : kSlots - 1) : 0;
    const auto mask = static_cast<std::uint16_t>(1u << i);
    if (!(used & mask)) {
      slot[i] = slot[last];
      used = static_cast<std::uint16_t>(used | mask);
    }
    last = i;
    return slot[i];
  }
};

template <class T>
struct TensionResult {
  T tension[kStrings]{};  // always within [t_min, t_max], never NaN
  Vec3<T> force{};        // Σ t_i u_i actually produced
  Vec3<T> torque{};       // Σ t_i m_i actually produced
  Flags flags = 0;        // from the geometry + invalid_input, degenerate_geometry, ill_conditioned, not_converged
  std::uint8_t iterations = 0;  // active-set changes made (0: the warm start was already optimal)
};

// Non-finite F, N, geometry or parameters → every tension at t_min (0 if t_min itself is unusable), the
// state reset and invalid_input set. `state` is read as the first guess and updated.
template <class T>
TensionResult<T> solve_tensions(const StringGeometry<T>& strings, const Vec3<T>& force, const Vec3<T>& torque,
                                const TensionParams<T>& params, TensionState& state);

}  // namespace hmp::spidar
