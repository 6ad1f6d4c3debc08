// The exponential integrator's matrix functions (boards/sim/plant/phi_chain): E = e^{τA}, P = ∫₀^τ e^{sA} ds
// and Q = ∫₀^τ e^{(τ−s)A}·s ds at every level τ = h/2^ℓ, against closed forms computed here in long double:
// a damped oscillator's e^{At} = e^{−ζωt}·(cos ω_d t·I + sin ω_d t / ω_d·(A + ζω·I)), P = A⁻¹(E − I),
// Q = A⁻¹(P − τI). Block-diagonal sets of oscillators from 10 Hz to 7 kHz (the plant's string modes at
// 10⁷ N/m), disguised by a diagonal similarity spanning eight decades (states in radians, amperes and
// metres), which the balancing must undo. Levels finer than the doubling's start are summed on their own
// when first read: computed now or later, every level must agree with the closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>
#include <vector>

#include "boards/sim/plant/phi_chain.hpp"

namespace hmp::sim::plant {
namespace {

using Real = long double;

struct Oscillator {
  Real omega, zeta;
};

// E, P, Q of one oscillator over t (2×2, row-major). For ωt < ½ the closed forms of P and Q cancel
// badly, and the series E = Σ (tA)^k/k!, P = t·Σ (tA)^k/(k+1)!, Q = t²·Σ (tA)^k/(k+2)! is used instead.
void closed_form(const Oscillator& o, Real t, Real (&e)[4], Real (&p)[4], Real (&q)[4]) {
  const Real w = o.omega, z = o.zeta, wd = w * std::sqrt(1 - z * z);
  const Real a[4] = {0, 1, -w * w, -2 * z * w};
  if (w * t < 0.5L) {
    Real power[4] = {1, 0, 0, 1}, fact = 1;  // (tA)^k and k!
    for (int i = 0; i < 4; ++i) e[i] = p[i] = q[i] = 0;
    for (int k = 0; k < 40; ++k) {
      for (int i = 0; i < 4; ++i) {
        e[i] += power[i] / fact;
        p[i] += t * power[i] / (fact * (k + 1));
        q[i] += t * t * power[i] / (fact * (k + 1) * (k + 2));
      }
      Real next[4];
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) next[i * 2 + j] = t * (power[i * 2] * a[j] + power[i * 2 + 1] * a[2 + j]);
      for (int i = 0; i < 4; ++i) power[i] = next[i];
      fact *= k + 1;
    }
    return;
  }
  const Real decay = std::exp(-z * w * t), c = std::cos(wd * t), s = std::sin(wd * t) / wd;
  for (int i = 0; i < 4; ++i) e[i] = decay * (s * (a[i] + (i == 0 || i == 3 ? z * w : 0)) + (i == 0 || i == 3 ? c : 0));
  // A⁻¹ = [[−2ζω, −1], [ω², 0]] / ω².
  const Real inv[4] = {-2 * z * w / (w * w), -1 / (w * w), 1, 0};
  const auto apply = [&](const Real(&m)[4], Real(&out)[4]) {
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) out[i * 2 + j] = inv[i * 2] * m[j] + inv[i * 2 + 1] * m[2 + j];
  };
  Real em[4] = {e[0] - 1, e[1], e[2], e[3] - 1};
  apply(em, p);
  Real pm[4] = {p[0] - t, p[1], p[2], p[3] - t};
  apply(pm, q);
}

// `before`: a matrix the chain is computed on first (its balancing then starts from that one's scale).
void check(const std::vector<Oscillator>& oscillators, double h, double tolerance, int eager_levels,
           const std::vector<double>& before = {}) {
  const int n = 2 * static_cast<int>(oscillators.size());
  // The similarity: state i scaled by 10^(8·i/n − 4), alternating up and down the range.
  std::vector<Real> d(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    d[static_cast<std::size_t>(i)] = std::pow(10.0L, (i % 2 ? 4.0L : -4.0L) * (i * 2.0L / n - 1));
  std::vector<double> a(static_cast<std::size_t>(n * n), 0.0);
  for (std::size_t k = 0; k < oscillators.size(); ++k) {
    const Real w = oscillators[k].omega, z = oscillators[k].zeta;
    const int b = 2 * static_cast<int>(k);
    const Real block[4] = {0, 1, -w * w, -2 * z * w};
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        a[static_cast<std::size_t>((b + i) * n + b + j)] = static_cast<double>(
            block[i * 2 + j] * d[static_cast<std::size_t>(b + i)] / d[static_cast<std::size_t>(b + j)]);
  }
  const int ld = PhiChain::stride(n);
  PhiChain chain(6);
  if (!before.empty()) chain.compute(before.data(), n, h, eager_levels);
  chain.compute(a.data(), n, h, eager_levels);
  for (int level = 0; level < 6; ++level) {
    const Real t = std::ldexp(static_cast<Real>(h), -level);
    const double* got[3] = {chain.exponential(level), chain.integral(level), chain.ramp(level)};
    for (std::size_t k = 0; k < oscillators.size(); ++k) {
      Real want[3][4];
      closed_form(oscillators[k], t, want[0], want[1], want[2]);
      const int b = 2 * static_cast<int>(k);
      for (int f = 0; f < 3; ++f) {
        // Each block compared in its own (unscaled) units, relative to its largest entry.
        Real scale = 0, worst = 0;
        for (int i = 0; i < 2; ++i)
          for (int j = 0; j < 2; ++j) {
            const std::size_t at = static_cast<std::size_t>((b + j) * ld + b + i);  // by columns
            const Real unscaled =
                static_cast<Real>(got[f][at]) * d[static_cast<std::size_t>(b + j)] / d[static_cast<std::size_t>(b + i)];
            scale = std::fmax(scale, std::fabs(want[f][i * 2 + j]));
            worst = std::fmax(worst, std::fabs(unscaled - want[f][i * 2 + j]));
          }
        EXPECT_LE(static_cast<double>(worst / scale), tolerance)
            << "function " << f << " (E, P, Q), level " << level << ", oscillator " << k;
      }
      // Nothing leaks between the blocks.
      for (int i = 0; i < n; ++i) {
        if (i / 2 == b / 2) continue;
        EXPECT_EQ(got[0][static_cast<std::size_t>(b * ld + i)], 0.0) << "row " << i;
      }
    }
  }
}

TEST(PhiChain, OscillatorsFromSoftToWireLikeStrings) {
  std::vector<Oscillator> set;
  for (int k = 0; k < 18; ++k)
    set.push_back({2 * std::numbers::pi_v<long double> * 10 * std::pow(700.0L, k / 17.0L), 0.005L + 0.02L * k});
  for (int eager : {6, 3, 1}) check(set, 1e-3, 1e-10, eager);
}

TEST(PhiChain, ShortAndLongSteps) {
  const std::vector<Oscillator> set = {{62.8L, 0.3L}, {4.5e4L, 0.0045L}, {1e3L, 0.9L}};
  for (double h : {1e-6, 1e-4, 1e-2})
    for (int eager : {6, 1}) check(set, h, 1e-10, eager);
}

// Balancing starts from the scale of the chain's last matrix: one whose states were scaled the other way
// round (the similarity's exponents negated) must not leave the next one less accurate.
TEST(PhiChain, BalancingFromAnotherMatrixScaleKeepsTheClosedForms) {
  const std::vector<Oscillator> set = {{62.8L, 0.3L}, {4.5e4L, 0.0045L}, {1e3L, 0.9L}, {6e3L, 0.02L}};
  const int n = 2 * static_cast<int>(set.size());
  std::vector<double> other(static_cast<std::size_t>(n * n), 0.0);
  for (int b = 0; b < n; b += 2) {
    const double up = std::pow(10.0, 3.0 * b / n - 4.0);  // its own similarity, unrelated to check()'s
    other[static_cast<std::size_t>(b * n + b + 1)] = up;
    other[static_cast<std::size_t>((b + 1) * n + b)] = -1e6 / up;
    other[static_cast<std::size_t>((b + 1) * n + b + 1)] = -50.0;
  }
  for (int eager : {6, 1}) check(set, 1e-3, 1e-10, eager, other);
}

// The quarter rows (the integrator's switch rows G·P(t_c), t_c = (c + 1)·h/4) against the products summed
// here in long double: a G of 5 rows with every third entry zero and rows of very different sizes, over a
// 13-state matrix (not a multiple of the chain's vector width), by P(h/4), P(h/2) and P(h) read from the
// chain, and by P(3h/4) from a second chain computed with that step. With some levels not kept, and with
// the doubling starting further down (a stiffer matrix), the rows are the same.
TEST(PhiChain, QuarterRowsAreTheRowsTimesTheIntegral) {
  const int n = 13, m = 5;
  for (double stiffness : {1.0, 1e3}) {
    std::vector<double> a(static_cast<std::size_t>(n * n)), g(static_cast<std::size_t>(m * n));
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        a[static_cast<std::size_t>(i * n + j)] = i == j                 ? -300.0 * stiffness * (1.5 + std::sin(1.0 + i))
                                                 : (i + 2 * j) % 5 == 0 ? 0.0
                                                                        : std::sin(1.0 + i * n + j) * 300.0;
    for (int k = 0; k < m; ++k)
      for (int j = 0; j < n; ++j)
        g[static_cast<std::size_t>(k * n + j)] =
            (k + j) % 3 == 0 ? 0.0 : std::cos(2.0 + k * n + j) * std::pow(10.0, k - 2);
    const double h = 1e-3;
    const int ld = PhiChain::stride(n);
    for (std::uint32_t kept : {~0u, 1u}) {
      std::vector<double> out(static_cast<std::size_t>(4 * m * n), -1.0);
      PhiChain::QuarterRows quarters;
      quarters.g = g.data();
      quarters.m = m;
      for (int c = 0; c < 4; ++c) quarters.out[static_cast<std::size_t>(c)] = &out[static_cast<std::size_t>(c * m * n)];
      PhiChain chain(3, kept), three_quarters(1);
      chain.compute(a.data(), n, h, 3, &quarters);
      three_quarters.compute(a.data(), n, 0.75 * h, 1);
      const double* p[4] = {chain.integral(2), chain.integral(1), three_quarters.integral(0), chain.integral(0)};
      for (int c = 0; c < 4; ++c)
        for (int k = 0; k < m; ++k)
          for (int j = 0; j < n; ++j) {
            Real want = 0, size = 0;
            for (int l = 0; l < n; ++l) {
              const Real term =
                  static_cast<Real>(g[static_cast<std::size_t>(k * n + l)]) * static_cast<Real>(p[c][j * ld + l]);
              want += term;
              size += std::fabs(term);
            }
            const Real err = std::fabs(static_cast<Real>(out[static_cast<std::size_t>((c * m + k) * n + j)]) - want);
            // P(3h/4) of the second chain agrees with the first's to ~1e-13, the others are the same numbers.
            EXPECT_LE(static_cast<double>(err), (c == 2 ? 1e-12 : 1e-14) * static_cast<double>(size) + 1e-300)
                << "stiffness " << stiffness << ", kept " << kept << ", quarter " << c << ", row " << k << ", column "
                << j;
          }
    }
  }
}

// multiply_add_rows (the switch rows along a step) against the sum taken here in long double, for every
// width from 1 to kMaxState (whole fours and every remainder) and row counts that are and are not
// multiples of four, entries of very different sizes; and the same sums over a matrix and vector padded
// with zero columns (a system with more states, all zero) bit for bit.
TEST(PhiChain, MultiplyAddRowsIsTheProductAddedAndScaled) {
  for (int n = 1; n <= kMaxState; ++n) {
    for (int rows : {1, 3, 4, 7, n}) {
      std::vector<double> m(static_cast<std::size_t>(rows * n)), v(static_cast<std::size_t>(n));
      std::vector<double> out(static_cast<std::size_t>(rows)), start(static_cast<std::size_t>(rows));
      for (int i = 0; i < rows; ++i)
        for (int j = 0; j < n; ++j)
          m[static_cast<std::size_t>(i * n + j)] = std::sin(1.0 + 7 * i + j) * std::pow(10.0, (i + 3 * j) % 9 - 4);
      for (int j = 0; j < n; ++j) v[static_cast<std::size_t>(j)] = std::cos(0.5 + j) * std::pow(10.0, j % 5 - 2);
      for (int i = 0; i < rows; ++i) start[static_cast<std::size_t>(i)] = out[static_cast<std::size_t>(i)] = i - 1.5;
      const double s = -0.37;
      multiply_add_rows(m.data(), rows, n, v.data(), s, out.data());
      for (int i = 0; i < rows; ++i) {
        Real sum = 0, size = 0;
        for (int j = 0; j < n; ++j) {
          const Real term = static_cast<Real>(m[static_cast<std::size_t>(i * n + j)]) *
                            static_cast<Real>(v[static_cast<std::size_t>(j)]);
          sum += term;
          size += std::fabs(term);
        }
        const Real want = static_cast<Real>(start[static_cast<std::size_t>(i)]) + static_cast<Real>(s) * sum;
        EXPECT_LE(static_cast<double>(std::fabs(static_cast<Real>(out[static_cast<std::size_t>(i)]) - want)),
                  1e-15 * (std::fabs(static_cast<double>(want)) + std::fabs(s) * static_cast<double>(size)))
            << "n " << n << ", rows " << rows << ", row " << i;
      }
      // Zero columns appended up to kMaxState: the same sums exactly.
      const int wide = kMaxState;
      std::vector<double> mw(static_cast<std::size_t>(rows * wide), 0.0), vw(static_cast<std::size_t>(wide), 0.0);
      for (int i = 0; i < rows; ++i)
        for (int j = 0; j < n; ++j) mw[static_cast<std::size_t>(i * wide + j)] = m[static_cast<std::size_t>(i * n + j)];
      for (int j = 0; j < n; ++j) vw[static_cast<std::size_t>(j)] = v[static_cast<std::size_t>(j)];
      std::vector<double> outw = start;
      multiply_add_rows(mw.data(), rows, wide, vw.data(), s, outw.data());
      for (int i = 0; i < rows; ++i)
        EXPECT_EQ(outw[static_cast<std::size_t>(i)], out[static_cast<std::size_t>(i)]) << "n " << n << ", row " << i;
    }
  }
}

// multiply_add_columns (a step's products by the chain's functions, stored by columns) against the sum
// taken here in long double, for every size from 1 to kMaxState, entries of very different sizes; and
// the same sums over the matrix and vector padded with zero rows and columns up to kMaxState (a system
// with more states, all zero) bit for bit.
TEST(PhiChain, MultiplyAddColumnsIsTheProductAddedAndScaled) {
  const auto entry = [](int i, int j) { return std::sin(1.0 + 7 * i + j) * std::pow(10.0, (i + 3 * j) % 9 - 4); };
  for (int n = 1; n <= kMaxState; ++n) {
    const int ld = PhiChain::stride(n), wide = PhiChain::stride(kMaxState);
    std::vector<double> m(static_cast<std::size_t>(n * ld), 0.0), mw(static_cast<std::size_t>(kMaxState * wide), 0.0);
    std::vector<double> v(static_cast<std::size_t>(kMaxState), 0.0), start(static_cast<std::size_t>(kMaxState));
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        m[static_cast<std::size_t>(j * ld + i)] = mw[static_cast<std::size_t>(j * wide + i)] = entry(i, j);
    for (int j = 0; j < n; ++j) v[static_cast<std::size_t>(j)] = std::cos(0.5 + j) * std::pow(10.0, j % 5 - 2);
    for (int i = 0; i < kMaxState; ++i) start[static_cast<std::size_t>(i)] = i - 1.5;
    const double s = -0.37;
    std::vector<double> out = start, outw = start;
    multiply_add_columns(m.data(), n, ld, v.data(), s, out.data());
    multiply_add_columns(mw.data(), kMaxState, wide, v.data(), s, outw.data());
    for (int i = 0; i < n; ++i) {
      Real sum = 0, size = 0;
      for (int j = 0; j < n; ++j) {
        const Real term = static_cast<Real>(entry(i, j)) * static_cast<Real>(v[static_cast<std::size_t>(j)]);
        sum += term;
        size += std::fabs(term);
      }
      const Real want = static_cast<Real>(start[static_cast<std::size_t>(i)]) + static_cast<Real>(s) * sum;
      EXPECT_LE(static_cast<double>(std::fabs(static_cast<Real>(out[static_cast<std::size_t>(i)]) - want)),
                1e-15 * (std::fabs(static_cast<double>(want)) + std::fabs(s) * static_cast<double>(size)))
          << "n " << n << ", row " << i;
      EXPECT_EQ(outw[static_cast<std::size_t>(i)], out[static_cast<std::size_t>(i)]) << "n " << n << ", row " << i;
    }
    for (int i = n; i < kMaxState; ++i)  // rows past n untouched
      EXPECT_EQ(out[static_cast<std::size_t>(i)], start[static_cast<std::size_t>(i)]) << "n " << n << ", row " << i;
  }
}

TEST(PhiChain, ZeroMatrixGivesTheIntegralsOfOneAndOfS) {
  const double a[9] = {};
  PhiChain chain(3);
  chain.compute(a, 3, 0.5, 3);
  for (int level = 0; level < 3; ++level) {
    const double t = std::ldexp(0.5, -level);
    for (int i = 0; i < 3; ++i) {
      const int at = i * PhiChain::stride(3) + i;
      EXPECT_EQ(chain.exponential(level)[at], 1.0);
      EXPECT_DOUBLE_EQ(chain.integral(level)[at], t);
      EXPECT_DOUBLE_EQ(chain.ramp(level)[at], t * t / 2);
    }
  }
}

// Chains sharing one workspace, computed one after the other and read in any order, and a chain whose
// finer levels are left until first read, give every level the same bit for bit as chains of their own
// computed at once: the workspace carries nothing from one computation to the next.
TEST(PhiChain, SharedWorkspaceAndLevelsLeftForLaterChangeNoBit) {
  const auto oscillators = [](double omega, double zeta, double coupling) {
    std::vector<double> a(36, 0.0);
    for (int b = 0; b < 6; b += 2) {
      const double w = omega * (1 + b);
      a[static_cast<std::size_t>(b * 6 + b + 1)] = 1e3;  // a position in mm, its rate in m/s
      a[static_cast<std::size_t>((b + 1) * 6 + b)] = -w * w * 1e-3;
      a[static_cast<std::size_t>((b + 1) * 6 + b + 1)] = -2 * zeta * w;
    }
    a[1 * 6 + 2] = a[3 * 6 + 4] = coupling;
    return a;
  };
  const std::vector<double> slow = oscillators(60.0, 0.05, 10.0), fast = oscillators(4.4e4, 0.001, -3e3);
  const double h = 1e-3;
  PhiChain::Workspace work;
  PhiChain shared_slow(6, ~0u, &work), shared_fast(6, ~0u, &work), own_slow(6), own_fast(6);
  shared_slow.compute(slow.data(), 6, h, 3, nullptr, 1u);  // level 0 only now
  shared_fast.compute(fast.data(), 6, h, 3);
  own_slow.compute(slow.data(), 6, h, 3);
  own_fast.compute(fast.data(), 6, h, 3);
  for (int level : {5, 1, 0, 4, 2, 3}) {
    const std::pair<PhiChain*, PhiChain*> pairs[2] = {{&shared_slow, &own_slow}, {&shared_fast, &own_fast}};
    for (const auto& [got, want] : pairs) {
      const double* g[3] = {got->exponential(level), got->integral(level), got->ramp(level)};
      const double* w[3] = {want->exponential(level), want->integral(level), want->ramp(level)};
      for (int f = 0; f < 3; ++f)
        for (int i = 0; i < 6 * PhiChain::stride(6); ++i)
          ASSERT_EQ(g[f][i], w[f][i]) << "function " << f << ", level " << level;
    }
  }
}

// The work matrices' storage starts on a cache line whatever the heap did before: allocations of odd sizes
// in between leave malloc's own results on 16-byte boundaries only.
TEST(LineAligned, EveryAllocationStartsOnACacheLine) {
  std::vector<std::vector<char>> odd;
  std::vector<LineAlignedDoubles> lines;
  for (int k = 1; k <= 40; ++k) {
    odd.emplace_back(static_cast<std::size_t>(k * 24 + 8));
    lines.emplace_back(static_cast<std::size_t>(k * 37 + 3), 1.0);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(lines.back().data()) % 64, 0u) << "allocation " << k;
  }
  LineAlignedDoubles copy = lines.back();
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(copy.data()) % 64, 0u);
  EXPECT_EQ(copy, lines.back());
}

}  // namespace
}  // namespace hmp::sim::plant
