#pragma once
// The matrix functions of the exponential integrator: for a square matrix A and a step h, the exponential
// E(τ) = e^{τA}, its integral P(τ) = ∫₀^τ e^{sA} ds (= τ·φ₁(τA)) and Q(τ) = ∫₀^τ e^{(τ−s)A}·s ds
// (= τ²·φ₂(τA)) at τ = h, h/2, h/4, … With them the linear system y' = A·y + b, b constant, moves
// exactly: y(τ) = y(0) + P(τ)·(A·y(0) + b).
//
// Method: balancing (a diagonal similarity by powers of two, so rows and columns of states in different
// units, radians, amperes and metres, have comparable norms), then a Taylor series of φ₂ at ‖τA‖₁ ≤ 8
// (as many terms as that norm needs) at the finest level the norm requires, and the doubling formulas
// E(2τ) = E(τ)², P(2τ) = P(τ) + E(τ)·P(τ), Q(2τ) = Q(τ) + E(τ)·Q(τ) + τ·P(τ) up to h. The levels the
// doubling passes are undone from the balancing only if the caller keeps them; a level finer than the
// doubling's start (or one passed and not kept) is computed the first time it is asked for: most
// linearisations never use them. Dense, double precision, n ≤ kMaxState; memory allocated at
// construction.
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <vector>

#include "boards/sim/plant/integrators.hpp"

namespace hmp::sim::plant {

// A matrix by its rows' nonzeros, gathered once and multiplied many times: row i < rows is value_of[k]
// at column_of[k] for k = start[i] … start[i + 1] − 1.
struct SparseRows {
  int first(int i) const { return start[static_cast<std::size_t>(i)]; }
  int last(int i) const { return start[static_cast<std::size_t>(i) + 1]; }
  int column(int l) const { return column_of[static_cast<std::size_t>(l)]; }
  double value(int, int l) const { return value_of[static_cast<std::size_t>(l)]; }

  int rows = 0;
  std::array<int, kMaxState + 1> start{};
  std::array<std::uint8_t, static_cast<std::size_t>(kMaxState) * kMaxState> column_of{};
  std::array<double, static_cast<std::size_t>(kMaxState) * kMaxState> value_of{};
  // The first `cols` columns of `rows` rows of a, row stride lda (rows, cols ≤ kMaxState).
  void gather(const double* a, int rows, int cols, int lda);
};

// out += s·(m·v) for `rows` rows of m, row-major with row stride n (the switch functions' rows along a step).
void multiply_add_rows(const double* m, int rows, int n, const double* v, double s, double* out);
// out += s·(m·v) for the n×n m stored by columns, column stride ld (PhiChain::stride(n)), its rows n … ld − 1
// zero: a step by the chain's functions.
void multiply_add_columns(const double* m, int n, int ld, const double* v, double s, double* out);

// Storage that starts on a cache line (64 bytes). The chain's padded rows are whole lines, so a row's
// vectors never straddle two lines; on malloc's 16-byte alignment they may, and whether they did depended
// on where earlier allocations had left the heap.
template <class T>
struct LineAligned {
  using value_type = T;
  static constexpr std::align_val_t kLine{64};
  LineAligned() = default;
  template <class U>
  LineAligned(const LineAligned<U>&) {}
  T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), kLine)); }
  void deallocate(T* p, std::size_t) { ::operator delete(p, kLine); }
  template <class U>
  bool operator==(const LineAligned<U>&) const {
    return true;
  }
};
using LineAlignedDoubles = std::vector<double, LineAligned<double>>;

class PhiChain {
 public:
  // The matrices a computation works in and leaves nothing in: several chains computed one after the
  // other (an integrator's cache of linearisations) share one, which then stays in the processor's caches
  // instead of each chain's cold copy being written over (71 kB of the 200 kB a chain holds).
  struct Workspace {
    LineAlignedDoubles x, phi, tmp;  // τ·B, φ₂ and a product: kPadded each
    LineAlignedDoubles e, p, q;      // E, P, Q of B at the level being worked on: kPadded each
    SparseRows rows;                 // the left factor of the products being taken
    SparseRows quarter_g;            // G·D, the quarter rows' left factor
    Workspace();
  };

  // The integral at the quarter steps t_c = (c + 1)·h/4, c = 0 … 3, projected on m rows G (an m×n
  // matrix of row stride n, m ≤ kMaxState): out[c] = G·P(t_c), m×n, stride n. Taken while the doubling
  // passes the levels h/4, h/2 and h, from its balanced matrices (the same numbers as from the plain
  // ones: the balancing's powers of two scale exactly).
  struct QuarterRows {
    const double* g = nullptr;
    int m = 0;
    std::array<double*, 4> out{};
  };

  // Room for `max_levels` levels (at most kMaxLevels), of which those in `kept` (bit ℓ for level ℓ) are
  // kept as the doubling passes them; any other level is summed on its own when first read.
  // `shared`: the workspace to compute in (it must outlive the chain), else the chain has its own.
  explicit PhiChain(int max_levels = kMaxLevels, std::uint32_t kept = ~0u, Workspace* shared = nullptr);
  // A is n×n, row-major with row stride n. Computes the kept levels of ℓ = 0 … levels − 1 (τ = h / 2^ℓ)
  // now (levels ≤ max_levels), any other up to max_levels − 1 when first asked for; and `quarters`, if
  // given. Of the kept levels only those in `keep_now` are kept now, the others when first asked for
  // (a chain most likely read at h only need not write its other levels).
  void compute(const double* a, int n, double h, int levels, const QuarterRows* quarters = nullptr,
               std::uint32_t keep_now = ~0u);
  // n×n by columns: entry (i, j) at [j·stride(n) + i], rows n … stride(n) − 1 zero; level < max_levels.
  const double* exponential(int level) { return at(e_, level); }
  const double* integral(int level) { return at(p_, level); }
  // Q(τ): the response to an input growing linearly from 0.
  const double* ramp(int level) { return at(q_, level); }
  // ‖D⁻¹·A·D‖₁ of the last computation's balanced A: a bound on its eigenvalues' moduli, in 1/s.
  double norm() const { return norm_; }

  static constexpr int kMaxLevels = 12;
  // The work matrices' rows are padded to a multiple of this many doubles: whole vectors of 8 or 4.
  static constexpr int kLanes = 8;
  // The columns' stride of the functions read for n states: n rounded up to whole vectors.
  static constexpr int stride(int n) { return (n + kLanes - 1) / kLanes * kLanes; }

 private:
  static constexpr std::size_t kPadded =
      static_cast<std::size_t>(kMaxState) * ((kMaxState + kLanes - 1) / kLanes * kLanes);  // × stride(kMaxState)
  static constexpr std::size_t kStride = kPadded;
  const double* at(const LineAlignedDoubles& functions, int level) {
    if (!ready_[static_cast<std::size_t>(level)]) sum_level(level);
    return &functions[static_cast<std::size_t>(level) * kStride];
  }
  // Q, P and E at τ = h / 2^level by the Taylor series, into the work matrices (balanced).
  void series(int level);
  // The work matrices, undone from the balancing, as level `level`.
  void keep(int level);
  // out = m·D⁻¹ for m rows of the product (row stride ld_), out of stride n_.
  void unbalance_columns(const double* product, int m, double* out) const;
  // The quarter rows' share of the level the work matrices hold.
  void quarter_rows(int level, const QuarterRows& quarters);
  // The work matrices hold level `from`: doubled up to level `to` (≤ from), keeping the levels in `keeping`
  // passed and `to`, and taking the quarter rows' share of the levels 2, 1 and 0 if given.
  void double_up(int from, int to, std::uint32_t keeping, const QuarterRows* quarters);
  // A level not kept: by its own series if finer than the doubling's start, else doubled up to again.
  void sum_level(int level);

  int max_levels_, n_ = 0, ld_ = 0;  // ld_: the work matrices' row stride
  std::uint32_t kept_;
  int start_ = 0;            // the level the doubling started from
  double h_ = 0, norm_ = 0;  // the step and ‖B‖₁ of the balanced matrix
  std::array<bool, kMaxLevels> ready_{};
  LineAlignedDoubles e_, p_, q_;    // max_levels × kStride each
  LineAlignedDoubles b_;            // B = D⁻¹·A·D, kPadded: a level asked for later starts from it
  std::vector<double> scale_;       // balancing: A = D·B·D⁻¹, D = diag(scale_)
  std::unique_ptr<Workspace> own_;  // when no workspace is shared
  Workspace* work_;
};

}  // namespace hmp::sim::plant
