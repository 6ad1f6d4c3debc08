#pragma once
// The matrix functions of the exponential integrator: for a square matrix A and a step h, the exponential
// E(τ) = e^{τA}, its integral P(τ) = ∫₀^τ e^{sA} ds (= τ·φ₁(τA)) and Q(τ) = ∫₀^τ e^{(τ−s)A}·s ds
// (= τ²·φ₂(τA)) at τ = h, h/2, h/4, … With them the linear system y' = A·y + b, b constant, moves
// exactly: y(τ) = y(0) + P(τ)·(A·y(0) + b).
//
// Method: balancing (a diagonal similarity by powers of two, so rows and columns of states in different
// units, radians, amperes and metres, have comparable norms), then a Taylor series of φ₂ at ‖τA‖₁ ≤ 8
// (as many terms as that norm needs) at the finest level the norm requires, and the doubling formulas
// E(2τ) = E(τ)², P(2τ) = P(τ) + E(τ)·P(τ), Q(2τ) = Q(τ) + E(τ)·Q(τ) + τ·P(τ) up to h. Levels finer
// than the doubling starts from are summed on their own, the first time they are asked for: most
// linearisations never use them. Dense, double precision, n ≤ kMaxState; memory allocated at
// construction.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "boards/sim/plant/integrators.hpp"

namespace hmp::sim::plant {

// A matrix by its rows' nonzeros, gathered once and multiplied many times: row i < rows is value[k] at
// column[k] for k = start[i] … start[i + 1] − 1.
struct SparseRows {
  int rows = 0;
  std::array<int, kMaxState + 1> start{};
  std::array<std::uint8_t, static_cast<std::size_t>(kMaxState) * kMaxState> column{};
  std::array<double, static_cast<std::size_t>(kMaxState) * kMaxState> value{};
  // The first `cols` columns of `rows` rows of a, row stride lda (rows, cols ≤ kMaxState).
  void gather(const double* a, int rows, int cols, int lda);
};

// out += s·(m·v) for `rows` rows of m, row-major with row stride n (a step by the chain's functions, the
// switch functions' rows along one).
void multiply_add_rows(const double* m, int rows, int n, const double* v, double s, double* out);

class PhiChain {
 public:
  // Room for `max_levels` levels (at most kMaxLevels).
  explicit PhiChain(int max_levels = kMaxLevels);
  // A is n×n, row-major with row stride n. Computes the levels ℓ = 0 … levels − 1 (τ = h / 2^ℓ) now
  // (levels ≤ max_levels), finer ones up to max_levels − 1 when first asked for.
  void compute(const double* a, int n, double h, int levels);
  // n×n, row-major, stride n; level < max_levels.
  const double* exponential(int level) { return at(e_, level); }
  const double* integral(int level) { return at(p_, level); }
  // Q(τ): the response to an input growing linearly from 0.
  const double* ramp(int level) { return at(q_, level); }
  // c = a·b for an m×n a of row stride lda and b one of the functions above (n×n, stride n), in the
  // chain's vector products (a's zeros skipped); c is m×n, stride n, and must not alias a or b. Uses the
  // chain's work matrices: b must have been read before the call (as an argument is).
  void left_multiply(const double* a, int m, int lda, const double* b, double* c);

  static constexpr int kMaxLevels = 12;
  // The work matrices' rows are padded to a multiple of this many doubles: whole vectors of 8 or 4.
  static constexpr int kLanes = 8;

 private:
  static constexpr std::size_t kStride = static_cast<std::size_t>(kMaxState) * kMaxState;
  static constexpr std::size_t kPadded =
      static_cast<std::size_t>(kMaxState) * ((kMaxState + kLanes - 1) / kLanes * kLanes);
  const double* at(const std::vector<double>& functions, int level) {
    if (!ready_[static_cast<std::size_t>(level)]) sum_level(level);
    return &functions[static_cast<std::size_t>(level) * kStride];
  }
  // Q, P and E at τ = h / 2^level by the Taylor series, into the work matrices (balanced).
  void series(int level);
  // The work matrices, undone from the balancing, as level `level`.
  void keep(int level);
  // A level finer than the doubling's start, by its own series.
  void sum_level(int level);

  int max_levels_, n_ = 0, ld_ = 0;  // ld_: the work matrices' row stride
  double h_ = 0, norm_ = 0;          // the step and ‖B‖₁ of the balanced matrix
  std::array<bool, kMaxLevels> ready_{};
  std::vector<double> e_, p_, q_;          // max_levels × kStride each
  std::vector<double> b_, x_, phi_, tmp_;  // B = D⁻¹·A·D, τ·B, φ₂ and a product: kPadded each
  std::vector<double> we_, wp_, wq_;       // E, P, Q of B at the level being worked on: kPadded each
  std::vector<double> scale_;              // balancing: A = D·B·D⁻¹, D = diag(scale_)
  SparseRows rows_;                        // the left factor of the products being taken
};

}  // namespace hmp::sim::plant
