#pragma once
// The matrix functions of the exponential integrator: for a square matrix A and a step h, the exponential
// E(τ) = e^{τA} and its integral P(τ) = ∫₀^τ e^{sA} ds (= τ·φ₁(τA)) at τ = h, h/2, h/4, … With them the
// linear system y' = A·y + b, b constant, moves exactly: y(τ) = y(0) + P(τ)·(A·y(0) + b).
//
// Method: balancing (a diagonal similarity by powers of two, so rows and columns of states in different
// units, radians, amperes and metres, have comparable norms), scaling and squaring with a Taylor series of
// φ₂ at ‖τA‖₁ ≤ 4 (as many terms as that norm needs), and the doubling formulas E(2τ) = E(τ)²,
// P(2τ) = P(τ) + E(τ)·P(τ), Q(2τ) = Q(τ) + E(τ)·Q(τ) + τ·P(τ), which give every coarser level on the way up. Dense, double precision, n ≤ kMaxState; memory allocated at construction.
#include <cstddef>
#include <vector>

#include "boards/sim/plant/integrators.hpp"

namespace hmp::sim::plant {

class PhiChain {
 public:
  // Room for `max_levels` levels (at most kMaxLevels).
  explicit PhiChain(int max_levels = kMaxLevels);
  // A is n×n, row-major with row stride n. Computes the levels ℓ = 0 … levels − 1 (τ = h / 2^ℓ);
  // levels ≤ max_levels.
  void compute(const double* a, int n, double h, int levels);
  int size() const { return n_; }
  int levels() const { return levels_; }
  // n×n, row-major, stride n.
  const double* exponential(int level) const { return &e_[static_cast<std::size_t>(level) * kStride]; }
  const double* integral(int level) const { return &p_[static_cast<std::size_t>(level) * kStride]; }
  // Q(τ) = ∫₀^τ e^{(τ−s)A}·s ds (= τ²·φ₂(τA)): the response to an input growing linearly from 0.
  const double* ramp(int level) const { return &q_[static_cast<std::size_t>(level) * kStride]; }
  // Squarings the last compute() took (log₂ of h over the Taylor series' step).
  int squarings() const { return squarings_; }

  static constexpr int kMaxLevels = 12;

 private:
  static constexpr std::size_t kStride = static_cast<std::size_t>(kMaxState) * kMaxState;
  int max_levels_, n_ = 0, levels_ = 0, squarings_ = 0;
  std::vector<double> e_, p_, q_;             // max_levels × kStride each
  std::vector<double> x_, phi_, tmp_;  // kStride each
  std::vector<double> w_, t_;         // [E | P | Q] and a product of it: 3·kStride each
  std::vector<double> scale_;                 // balancing: A = D·B·D⁻¹, D = diag(scale_)
};

// c = a·b for n×n row-major matrices (stride n); c must not alias a or b.
void multiply(const double* a, const double* b, double* c, int n);
// c = a·b for an m×n a and an n×n b (row-major); c must not alias.
void multiply_rows(const double* a, int m, const double* b, double* c, int n);

}  // namespace hmp::sim::plant
