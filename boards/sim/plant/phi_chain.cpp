#include "boards/sim/plant/phi_chain.hpp"

#include <cmath>

#include "boards/sim/plant/integrators.hpp"

namespace hmp::sim::plant {

namespace {

// The Taylor series of φ₂ is summed at ‖X‖₁ ≤ 4 (terms of up to 4²/4! ≈ 0.7 of I: no cancellation to
// speak of), with terms until the first left out is below 10⁻¹⁷: each term is a product by the sparse X,
// a tenth of a doubling's dense products, so a larger norm and more terms cost less than more levels.
constexpr double kTaylorNorm = 4.0;
constexpr int kMaxTaylorTerms = 40;

int taylor_terms(double norm) {
  double term = 1.0;  // ‖X‖^k / (k + 2)!, the bound of the first term left out after k − 1
  for (int k = 1; k <= kMaxTaylorTerms; ++k) {
    term *= norm / (k + 2);
    if (term < 1e-17) return k;
  }
  return kMaxTaylorTerms;
}

// Parlett–Reinsch balancing by powers of two: on return b = D⁻¹·a·D with D = diag(scale).
void balance(const double* a, double* b, double* scale, int n) {
  for (int i = 0; i < n * n; ++i) b[i] = a[i];
  for (int i = 0; i < n; ++i) scale[i] = 1.0;
  for (int sweep = 0; sweep < 100; ++sweep) {
    bool done = true;
    for (int i = 0; i < n; ++i) {
      double c = 0, r = 0;
      for (int j = 0; j < n; ++j) {
        if (j == i) continue;
        c += std::fabs(b[j * n + i]);
        r += std::fabs(b[i * n + j]);
      }
      if (c == 0 || r == 0) continue;
      const double s = c + r;
      double f = 1;
      while (c < r / 2) { c *= 4; f *= 2; }
      while (c > r * 2) { c /= 4; f /= 2; }
      if ((c + r) / f < 0.95 * s) {
        done = false;
        scale[i] *= f;
        for (int j = 0; j < n; ++j) b[i * n + j] /= f;
        for (int j = 0; j < n; ++j) b[j * n + i] *= f;
      }
    }
    if (done) break;
  }
}

double norm1(const double* a, int n) {
  double best = 0;
  for (int j = 0; j < n; ++j) {
    double s = 0;
    for (int i = 0; i < n; ++i) s += std::fabs(a[i * n + j]);
    best = std::fmax(best, s);
  }
  return best;
}

// The dense products are most of a linearisation's cost: on x86-64 they are built twice, for AVX2 with FMA
// and for the baseline, and the loader picks the one the CPU runs (a quarter less time per linearisation).
#if defined(__x86_64__)
#define HMP_VECTOR_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define HMP_VECTOR_CLONES
#endif

// c = a·b: a is m×k, b is k×cols, row-major; c must not alias either.
HMP_VECTOR_CLONES void product(const double* a, int m, int k, const double* b, int cols, double* c) {
  for (int i = 0; i < m; ++i) {
    double* row = c + i * cols;
    for (int j = 0; j < cols; ++j) row[j] = 0;
    for (int l = 0; l < k; ++l) {
      const double ail = a[i * k + l];
      if (ail == 0) continue;  // the plant's matrices keep many exact zeros
      const double* bl = b + l * cols;
      for (int j = 0; j < cols; ++j) row[j] += ail * bl[j];
    }
  }
}

// out = D·m·D⁻¹ (undoes the balancing); m has row stride `stride`.
void unbalance(const double* m, int stride, const double* scale, double* out, int n) {
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) out[i * n + j] = m[i * stride + j] * scale[i] / scale[j];
}

}  // namespace

void multiply_rows(const double* a, int m, const double* b, double* c, int n) { product(a, m, n, b, n, c); }

void multiply(const double* a, const double* b, double* c, int n) { product(a, n, n, b, n, c); }

PhiChain::PhiChain(int max_levels)
    : max_levels_(max_levels < 1 ? 1 : (max_levels > kMaxLevels ? kMaxLevels : max_levels)),
      e_(max_levels_ * kStride), p_(max_levels_ * kStride), q_(max_levels_ * kStride), x_(kStride), phi_(kStride),
      tmp_(kStride), w_(3 * kStride), t_(3 * kStride), scale_(kMaxState) {}

void PhiChain::compute(const double* a, int n, double h, int levels) {
  n_ = n;
  levels_ = levels < 1 ? 1 : (levels > max_levels_ ? max_levels_ : levels);
  const int nn = n * n;
  double* x = x_.data();
  balance(a, x, scale_.data(), n);
  // Squarings: enough for the Taylor series' norm, and at least enough to pass every level asked for.
  const double norm = h * norm1(x, n);
  int s = norm > kTaylorNorm ? static_cast<int>(std::ceil(std::log2(norm / kTaylorNorm))) : 0;
  if (s < levels_ - 1) s = levels_ - 1;
  squarings_ = s;
  const double tau = std::ldexp(h, -s);
  for (int i = 0; i < nn; ++i) x[i] *= tau;
  // φ₂(X) = ½·(I + X/3·(I + X/4·(…))) by Horner; then φ₁ = I + X·φ₂ and e^X = I + X·φ₁.
  double* phi = phi_.data();
  double* tmp = tmp_.data();
  for (int i = 0; i < nn; ++i) phi[i] = 0;
  for (int i = 0; i < n; ++i) phi[i * n + i] = 1;
  for (int k = taylor_terms(std::ldexp(norm, -s)); k >= 1; --k) {
    multiply(x, phi, tmp, n);
    const double inv = 1.0 / (k + 2);
    for (int i = 0; i < nn; ++i) phi[i] = tmp[i] * inv;
    for (int i = 0; i < n; ++i) phi[i * n + i] += 1;
  }
  // The three functions side by side, row i of each in row i of w = [E | P | Q] (n × 3n), so that one
  // product E·w doubles all three.
  const int w3 = 3 * n;
  double* w = w_.data();
  double* t = t_.data();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) w[i * w3 + 2 * n + j] = 0.5 * tau * tau * phi[i * n + j];  // Q(τ) = τ²·φ₂(X)
  multiply(x, phi, tmp, n);
  for (int i = 0; i < nn; ++i) phi[i] = 0.5 * tmp[i];
  for (int i = 0; i < n; ++i) phi[i * n + i] += 1;  // φ₁(X)
  multiply(x, phi, tmp, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      w[i * w3 + j] = tmp[i * n + j] + (i == j ? 1.0 : 0.0);  // E(τ) = I + X·φ₁(X)
      w[i * w3 + n + j] = tau * phi[i * n + j];               // P(τ) = τ·φ₁(X)
    }
  // Level s is τ; double up to level 0 (= h), keeping the levels asked for:
  //   E(2τ) = E², P(2τ) = P + E·P, Q(2τ) = Q + E·Q + τ·P.
  for (int level = s;; --level) {
    if (level < levels_) {
      const std::size_t at = static_cast<std::size_t>(level) * kStride;
      unbalance(w, w3, scale_.data(), &e_[at], n);
      unbalance(w + n, w3, scale_.data(), &p_[at], n);
      unbalance(w + 2 * n, w3, scale_.data(), &q_[at], n);
    }
    if (level == 0) break;
    const double step = std::ldexp(h, -level);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) tmp[i * n + j] = w[i * w3 + j];
    product(tmp, n, n, w, w3, t);
    for (int i = 0; i < n; ++i) {
      double* row = w + i * w3;
      const double* prod = t + i * w3;
      for (int j = 0; j < n; ++j) {
        row[2 * n + j] += prod[2 * n + j] + step * row[n + j];
        row[n + j] += prod[n + j];
        row[j] = prod[j];
      }
    }
  }
}

}  // namespace hmp::sim::plant
