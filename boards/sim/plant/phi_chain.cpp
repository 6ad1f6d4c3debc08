#include "boards/sim/plant/phi_chain.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>

#include "boards/sim/plant/integrators.hpp"

namespace hmp::sim::plant {

namespace {

// The Taylor series of φ₂ is summed at ‖X‖₁ ≤ 8, forward, until what is left after a term is below
// 10⁻¹³ (of φ₂(0) = I/2; the integrator's errors are 10⁻⁴ of the force and more, and the terms down to
// 10⁻¹⁷ cost 4 % of the carried grip's run at 10⁵ N/m): each term is a product by the sparse X, about a
// twelfth of a doubling's three dense products, so a larger norm and more terms cost less than more
// levels. The bound is set by cancellation: the terms of a lightly damped mode grow to 8⁶/8! ≈ 6.5 of I
// before they fall; at 16, a 7 kHz string mode over 10 ms lost E's tenth digit
// (tests/boards/sim/phi_chain_test.cpp), at 8 it keeps it.
constexpr double kTaylorNorm = 8.0;
constexpr double kTaylorTail = 1e-13;
constexpr int kMaxTaylorTerms = 60;

// Parlett–Reinsch balancing by powers of two: on return b = D⁻¹·a·D with D = diag(scale); a has row
// stride n, b row stride ld (its columns n … ld − 1 zero). The sweeps start from the scale passed in
// (powers of two, or all 1): a linearisation of the same plant a little further along is balanced by
// nearly the same D, and starting there saves most of the ~5 sweeps a start from 1 takes.
void balance(const double* a, double* b, int ld, double* scale, int n) {
  for (int i = 0; i < n; ++i) {
    const double inverse = 1 / scale[i];  // a power of two: exact
    for (int j = 0; j < ld; ++j) b[i * ld + j] = j < n ? a[i * n + j] * inverse * scale[j] : 0.0;
  }
  for (int sweep = 0; sweep < 100; ++sweep) {
    bool done = true;
    for (int i = 0; i < n; ++i) {
      double c = 0, r = 0;
      for (int j = 0; j < n; ++j) {
        if (j == i) continue;
        c += std::fabs(b[j * ld + i]);
        r += std::fabs(b[i * ld + j]);
      }
      if (c == 0 || r == 0) continue;
      const double s = c + r;
      double f = 1;
      while (c < r / 2) {
        c *= 4;
        f *= 2;
      }
      while (c > r * 2) {
        c /= 4;
        f /= 2;
      }
      if ((c + r) / f < 0.95 * s) {
        done = false;
        scale[i] *= f;
        for (int j = 0; j < n; ++j) b[i * ld + j] /= f;
        for (int j = 0; j < n; ++j) b[j * ld + i] *= f;
      }
    }
    if (done) break;
  }
}

// The products are most of a linearisation's cost: on x86-64 they are built twice, for AVX2 with FMA and
// for the baseline, and the loader picks the one the CPU runs.
#if defined(__x86_64__)
#define HMP_VECTOR_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define HMP_VECTOR_CLONES
#endif
// Clang clones plain functions only: there the function templates are built for the baseline.
#if defined(__clang__)
#define HMP_VECTOR_CLONES_TEMPLATE
#else
#define HMP_VECTOR_CLONES_TEMPLATE HMP_VECTOR_CLONES
#endif

HMP_VECTOR_CLONES double norm1(const double* a, int ld, int n) {
  double column[kMaxState] = {};
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) column[j] += std::fabs(a[i * ld + j]);
  double best = 0;
  for (int j = 0; j < n; ++j) best = std::fmax(best, column[j]);
  return best;
}

// The element-wise steps of the doubling, over whole padded matrices of `size` doubles: y += t + s·x;
// and y += t.
HMP_VECTOR_CLONES void add_scaled(const double* t, double s, const double* x, double* y, int size) {
  for (int i = 0; i < size; ++i) y[i] += t[i] + s * x[i];
}
HMP_VECTOR_CLONES void add(const double* t, double* y, int size) {
  for (int i = 0; i < size; ++i) y[i] += t[i];
}

// The chain's own matrices have rows padded to a multiple of kLanes doubles (their extra columns zero),
// so that a row of a product is whole vectors: c_i = Σ_l a_il·b_l with the row c_i held in registers
// throughout, over a's nonzeros only (a plant's Jacobian is three quarters zeros). Vectors of 4 (AVX2)
// or, where the CPU has AVX-512, of 8: three and five times the plain loop's speed at n = 37.
using Vector4 = double __attribute__((vector_size(32), aligned(8)));
using Vector8 = double __attribute__((vector_size(64), aligned(8)));
constexpr int kLanes = PhiChain::kLanes;
static_assert(kMaxState <= 256, "SparseRows keeps column indices in a byte");

// Each row's sums of a·b, handed to `sink(i, sums)` (sums: NV vectors V, the row's ld doubles), b of row
// stride ld = NV vectors V. The left factor a is a SparseRows (its nonzeros) or a DenseRows.
template <class V, int NV, class Left, class Sink>
[[gnu::always_inline]] inline void sparse_rows(const Left& a, const double* b, int ld, Sink& sink) {
  constexpr int kWidth = sizeof(V) / sizeof(double);
  for (int i = 0; i < a.rows; ++i) {
    V sum[NV] = {};
    for (int l = a.first(i); l < a.last(i); ++l) {
      const V v = V{} + a.value(i, l);
      const double* bl = b + a.column(l) * ld;
      for (int q = 0; q < NV; ++q) {
        V x;
        std::memcpy(&x, bl + kWidth * q, sizeof x);
        sum[q] += v * x;
      }
    }
    sink(i, sum);
  }
}

// A dense left factor, read in place: a product of two dense matrices (the doubling's E·E, E·P, E·Q)
// has nothing to skip, and gathering the entries first cost more than the zeros saved.
struct DenseRows {
  const double* a;
  int rows, cols, lda;
  int first(int) const { return 0; }
  int last(int) const { return cols; }
  int column(int l) const { return l; }
  double value(int i, int l) const { return a[i * lda + l]; }
};

// sparse_rows for the NV that ld needs, ld a multiple of kLanes up to kMaxState rounded up.
template <class V, class Left, class Sink, int... K>
[[gnu::always_inline]] inline void sparse_rows_of(std::integer_sequence<int, K...>, const Left& a, const double* b,
                                                  int ld, Sink& sink) {
  constexpr int kPerLane = kLanes / static_cast<int>(sizeof(V) / sizeof(double));
  ((ld == kLanes * (K + 1) ? sparse_rows<V, kPerLane*(K + 1)>(a, b, ld, sink) : void()), ...);
}
using LaneGroups = std::make_integer_sequence<int, (kMaxState + kLanes - 1) / kLanes>;

// The rows stored: c = a·b.
struct Store {
  double* c;
  int ld;
  template <class V, int NV>
  [[gnu::always_inline]] void operator()(int i, const V (&sum)[NV]) const {
    for (int q = 0; q < NV; ++q)
      std::memcpy(c + i * ld + q * static_cast<int>(sizeof(V) / sizeof(double)), &sum[q], sizeof(V));
  }
};

// A term of the series from the one before, in the same pass: term = s·(a·b), total += term, and the
// columns' sums of |term| (for its 1-norm) in column_sums.
struct NextTerm {
  double *term, *total, *column_sums;
  double s;
  int ld;
  template <class V, int NV>
  [[gnu::always_inline]] void operator()(int i, const V (&sum)[NV]) const {
    constexpr int kWidth = sizeof(V) / sizeof(double);
    for (int q = 0; q < NV; ++q) {
      const V t = sum[q] * s;
      V acc, column;
      std::memcpy(term + i * ld + kWidth * q, &t, sizeof t);
      std::memcpy(&acc, total + i * ld + kWidth * q, sizeof acc);
      acc += t;
      std::memcpy(total + i * ld + kWidth * q, &acc, sizeof acc);
      std::memcpy(&column, column_sums + kWidth * q, sizeof column);
      column += t < 0 ? -t : t;
      std::memcpy(column_sums + kWidth * q, &column, sizeof column);
    }
  }
};

template <class Left, class Sink>
HMP_VECTOR_CLONES_TEMPLATE void sparse_product4(const Left& a, const double* b, int ld, Sink sink) {
  sparse_rows_of<Vector4>(LaneGroups{}, a, b, ld, sink);
}

#if defined(__x86_64__)
template <class Left, class Sink>
__attribute__((target("arch=x86-64-v4"))) void sparse_product8(const Left& a, const double* b, int ld, Sink sink) {
  sparse_rows_of<Vector8>(LaneGroups{}, a, b, ld, sink);
}
#endif

#if defined(__x86_64__)
// Whether the CPU runs the vectors of 8 (AVX-512): asked once.
bool wide_vectors() {
  static const bool wide = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq");
  return wide;
}
#endif

// The rows of a·b for b of row stride ld (a multiple of kLanes, columns n … ld − 1 zero) to `sink`.
template <class Left, class Sink>
void sparse_product(const Left& a, const double* b, int ld, Sink sink) {
#if defined(__x86_64__)
  if (wide_vectors()) return sparse_product8(a, b, ld, sink);
#endif
  sparse_product4(a, b, ld, sink);
}

// c = a·b, c with a's rows and b's stride ld; c must not alias b.
template <class Left>
void sparse_product(const Left& a, const double* b, double* c, int ld) {
  sparse_product(a, b, ld, Store{c, ld});
}

// out = D·m·D⁻¹ (undoes the balancing), stored by columns: m has row stride `ld`, out is column-major
// with column stride ld, the rows n … ld − 1 of each column zero.
HMP_VECTOR_CLONES void unbalance_to_columns(const double* __restrict m, int ld, const double* scale,
                                            double* __restrict out, int n) {
  for (int j = 0; j < n; ++j) {
    const double inverse = 1 / scale[j];  // a power of two: exact
    double* column = out + j * ld;
    for (int i = 0; i < n; ++i) column[i] = m[i * ld + j] * scale[i] * inverse;
    for (int i = n; i < ld; ++i) column[i] = 0;
  }
}

// out_i += s·Σ_j m_ij·v_j for R rows of m (row stride n) from row `first`. Each row is summed in four
// running sums (column j in sum j mod 4, the columns after the last whole four added to sums 0–2 by
// hand) added up in one order. One running sum a row waits on each add before the next: at n = 37 the
// sub-steps of frame_edge at 10⁴ N/m then spent a quarter of the run in these products. The fixed
// order also sums a system with more states, all zero, bit for bit like the smaller one.
template <int R>
[[gnu::always_inline]] inline void multiply_add_some(const double* m, int first, int n, const double* v, double s,
                                                     double* out) {
  const int whole = n / 4 * 4, left = n - whole;
  Vector4 sum[R] = {};
  for (int j = 0; j < whole; j += 4) {
    Vector4 x;
    std::memcpy(&x, v + j, sizeof x);
    for (int r = 0; r < R; ++r) {
      Vector4 a;
      std::memcpy(&a, m + (first + r) * n + j, sizeof a);
      sum[r] += a * x;
    }
  }
  for (int r = 0; r < R; ++r) {
    const double* row = m + (first + r) * n + whole;
    double l0 = sum[r][0], l1 = sum[r][1], l2 = sum[r][2];
    if (left > 0) l0 += row[0] * v[whole];
    if (left > 1) l1 += row[1] * v[whole + 1];
    if (left > 2) l2 += row[2] * v[whole + 2];
    out[first + r] += s * ((l0 + l1) + (l2 + sum[r][3]));
  }
}

// out_i += s·Σ_j m_ij·v_j over a column-major m: each vector of NV holds rows side by side, and every
// row's sum runs over the columns in order, one multiply–add each, so vectors of 4 and of 8 give the
// same bits. Three times the row-wise kernel's speed at n = 37 with vectors of 8: no sum waits on its
// own last add, the rows' sums being independent.
template <class V, int NV>
[[gnu::always_inline]] inline void columns(const double* m, int n, int ld, const double* v, double s, double* out) {
  constexpr int kWidth = sizeof(V) / sizeof(double);
  V sum[NV] = {};
  for (int j = 0; j < n; ++j) {
    const V x = V{} + v[j];
    const double* column = m + j * ld;
    for (int q = 0; q < NV; ++q) {
      V a;
      std::memcpy(&a, column + kWidth * q, sizeof a);
      sum[q] += a * x;
    }
  }
  double total[NV * kWidth];
  std::memcpy(total, sum, sizeof total);
  for (int i = 0; i < n; ++i) out[i] += s * total[i];
}

template <class V, int... K>
[[gnu::always_inline]] inline void columns_of(std::integer_sequence<int, K...>, const double* m, int n, int ld,
                                              const double* v, double s, double* out) {
  constexpr int kPerLane = kLanes / static_cast<int>(sizeof(V) / sizeof(double));
  ((ld == kLanes * (K + 1) ? columns<V, kPerLane*(K + 1)>(m, n, ld, v, s, out) : void()), ...);
}

HMP_VECTOR_CLONES void columns4(const double* m, int n, int ld, const double* v, double s, double* out) {
  columns_of<Vector4>(LaneGroups{}, m, n, ld, v, s, out);
}

#if defined(__x86_64__)
__attribute__((target("arch=x86-64-v4"))) void columns8(const double* m, int n, int ld, const double* v, double s,
                                                        double* out) {
  columns_of<Vector8>(LaneGroups{}, m, n, ld, v, s, out);
}
#endif

}  // namespace

void multiply_add_columns(const double* m, int n, int ld, const double* v, double s, double* out) {
#if defined(__x86_64__)
  if (wide_vectors()) return columns8(m, n, ld, v, s, out);
#endif
  columns4(m, n, ld, v, s, out);
}

HMP_VECTOR_CLONES void multiply_add_rows(const double* m, int rows, int n, const double* v, double s, double* out) {
  int i = 0;
  for (; i + 4 <= rows; i += 4) multiply_add_some<4>(m, i, n, v, s, out);
  for (; i < rows; ++i) multiply_add_some<1>(m, i, n, v, s, out);
}

PhiChain::Workspace::Workspace() : x(kPadded), phi(kPadded), tmp(kPadded), e(kPadded), p(kPadded), q(kPadded) {}

PhiChain::PhiChain(int max_levels, std::uint32_t kept, Workspace* shared)
    : max_levels_(max_levels < 1 ? 1 : (max_levels > kMaxLevels ? kMaxLevels : max_levels)),
      kept_(kept),
      e_(max_levels_ * kStride),
      p_(max_levels_ * kStride),
      q_(max_levels_ * kStride),
      b_(kPadded),
      scale_(kMaxState, 1.0),
      own_(shared == nullptr ? std::make_unique<Workspace>() : nullptr),
      work_(shared == nullptr ? own_.get() : shared) {}

void PhiChain::compute(const double* a, int n, double h, int levels, const QuarterRows* quarters,
                       std::uint32_t keep_now) {
  n_ = n;
  ld_ = (n + kLanes - 1) / kLanes * kLanes;
  h_ = h;
  ready_.fill(false);
  if (levels > max_levels_) levels = max_levels_;
  balance(a, b_.data(), ld_, scale_.data(), n);
  norm_ = norm1(b_.data(), ld_, n);
  // Squarings: enough for the Taylor series' norm, and at least enough to pass every level asked for now.
  const double norm = h * norm_;
  int s = norm > kTaylorNorm ? static_cast<int>(std::ceil(std::log2(norm / kTaylorNorm))) : 0;
  if (s < levels - 1) s = levels - 1;
  if (quarters != nullptr) {
    if (s < 2) s = 2;
    double* scaled = work_->tmp.data();
    for (int i = 0; i < quarters->m; ++i)
      for (int j = 0; j < n; ++j) scaled[i * n + j] = quarters->g[i * n + j] * scale_[static_cast<std::size_t>(j)];
    work_->quarter_g.gather(scaled, quarters->m, n, n);
  }
  start_ = s;
  series(s);
  double_up(s, 0, kept_ & keep_now, quarters);
}

// The work matrices hold level `from`; double them up to level `to`, keeping the kept levels passed
// (those kept already, when a level not kept is doubled up to again, are left as they are):
//   E(2τ) = E², P(2τ) = P + E·P, Q(2τ) = Q + E·Q + τ·P.
void PhiChain::double_up(int from, int to, std::uint32_t keeping, const QuarterRows* quarters) {
  const int n = n_, size = n * ld_;
  double *e = work_->e.data(), *p = work_->p.data(), *q = work_->q.data(), *t = work_->tmp.data(), *u = work_->x.data();
  for (int level = from;; --level) {
    const bool wanted = (keeping >> level & 1u) != 0 || level == to;
    if (level < max_levels_ && wanted && !ready_[static_cast<std::size_t>(level)]) keep(level);
    if (quarters != nullptr && level <= 2) quarter_rows(level, *quarters);
    if (level == to) break;
    const double step = std::ldexp(h_, -level);
    const DenseRows left{e, n, n, ld_};
    sparse_product(left, q, t, ld_);
    add_scaled(t, step, p, q, size);
    sparse_product(left, p, t, ld_);
    add(t, p, size);
    sparse_product(left, e, u, ld_);
    std::memcpy(e, u, sizeof(double) * static_cast<std::size_t>(size));
  }
}

void PhiChain::series(int level) {
  const int n = n_, ld = ld_, size = n * ld;
  const double tau = std::ldexp(h_, -level);
  double *x = work_->x.data(), *t = work_->tmp.data();
  for (int i = 0; i < size; ++i) x[i] = tau * b_[static_cast<std::size_t>(i)];
  work_->rows.gather(x, n, n, ld);
  // φ₂(X) = Σ_k X^k/(k + 2)!: term_k = X·term_{k−1}/(k + 2). After term_k the rest is at most
  // ‖term_k‖₁·Σ_j (‖X‖₁/(k + 3))^j; the terms of the plant's X shrink far faster than ‖X‖₁^k/(k + 2)!
  // (its norm is inflated by couplings between states of different speeds), so the sum stops at the
  // terms actually needed, not at that bound.
  double *term = work_->phi.data(), *next = t;
  double* sum = work_->q.data();
  for (int i = 0; i < size; ++i) term[i] = 0;
  for (int i = 0; i < n; ++i) term[i * ld + i] = 0.5;
  for (int i = 0; i < size; ++i) sum[i] = term[i];
  const double norm = tau * norm_;
  for (int k = 1; k <= kMaxTaylorTerms; ++k) {
    alignas(64) double column_sums[kMaxState + kLanes] = {};
    sparse_product(work_->rows, term, ld, NextTerm{next, sum, column_sums, 1.0 / (k + 2), ld});
    std::swap(term, next);
    double term_norm = 0;
    for (int j = 0; j < n; ++j) term_norm = std::fmax(term_norm, column_sums[j]);
    const double ratio = norm / (k + 3);
    if (ratio < 1 && term_norm < kTaylorTail * (1 - ratio)) break;
  }
  double *e = work_->e.data(), *p = work_->p.data(), *q = work_->q.data();
  sparse_product(work_->rows, q, p, ld);
  for (int i = 0; i < n; ++i) p[i * ld + i] += 1;  // φ₁(X) = I + X·φ₂(X)
  sparse_product(work_->rows, p, e, ld);
  for (int i = 0; i < n; ++i) e[i * ld + i] += 1;  // E = e^X = I + X·φ₁(X)
  for (int i = 0; i < size; ++i) {
    q[i] *= tau * tau;  // Q = τ²·φ₂(X)
    p[i] *= tau;        // P = τ·φ₁(X)
  }
}

void SparseRows::gather(const double* a, int rows_in, int cols, int lda) {
  rows = rows_in;
  int count = 0;
  for (int i = 0; i < rows; ++i) {
    start[static_cast<std::size_t>(i)] = count;
    for (int j = 0; j < cols; ++j) {
      // Written whether zero or not, kept by moving on only past a nonzero: no branch to mispredict on a
      // sparse row's pattern.
      const double v = a[i * lda + j];
      column_of[static_cast<std::size_t>(count)] = static_cast<std::uint8_t>(j);
      value_of[static_cast<std::size_t>(count)] = v;
      count += v != 0 ? 1 : 0;
    }
  }
  start[static_cast<std::size_t>(rows)] = count;
}

void PhiChain::unbalance_columns(const double* product, int m, double* out) const {
  double inverse[kMaxState];
  for (int j = 0; j < n_; ++j) inverse[j] = 1 / scale_[static_cast<std::size_t>(j)];  // powers of two: exact
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < n_; ++j) out[i * n_ + j] = product[i * ld_ + j] * inverse[j];
}

// G·P = (G·D)·B_P·D⁻¹ for P(h/4), P(h/2) and P(h) from their levels; P(3h/4) = P(h/2) + E(h/2)·P(h/4),
// so level 2's P is kept (balanced, in the workspace's φ₂: the series is done with it) until level 1's E.
void PhiChain::quarter_rows(int level, const QuarterRows& quarters) {
  const int m = quarters.m;
  double* product = work_->tmp.data();
  sparse_product(work_->quarter_g, work_->p.data(), product, ld_);
  unbalance_columns(product, m, quarters.out[level == 2 ? 0 : level == 1 ? 1 : 3]);
  if (level == 2) {
    std::memcpy(work_->phi.data(), work_->p.data(), sizeof(double) * static_cast<std::size_t>(n_ * ld_));
  } else if (level == 1) {
    sparse_product(work_->quarter_g, work_->e.data(), product, ld_);  // G·D·B_E(h/2)
    work_->rows.gather(product, m, n_, ld_);
    sparse_product(work_->rows, work_->phi.data(), work_->x.data(), ld_);
    double* three_quarters = quarters.out[2];
    unbalance_columns(work_->x.data(), m, three_quarters);
    const double* half = quarters.out[1];
    for (int i = 0; i < m * n_; ++i) three_quarters[i] += half[i];
  }
}

void PhiChain::keep(int level) {
  const std::size_t at = static_cast<std::size_t>(level) * kStride;
  unbalance_to_columns(work_->e.data(), ld_, scale_.data(), &e_[at], n_);
  unbalance_to_columns(work_->p.data(), ld_, scale_.data(), &p_[at], n_);
  unbalance_to_columns(work_->q.data(), ld_, scale_.data(), &q_[at], n_);
  ready_[static_cast<std::size_t>(level)] = true;
}

void PhiChain::sum_level(int level) {
  // A level the doubling passed without keeping it is doubled up to again from where it started.
  const int from = level > start_ ? level : start_;
  series(from);
  double_up(from, level, kept_, nullptr);
}

}  // namespace hmp::sim::plant
