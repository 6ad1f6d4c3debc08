#include "boards/sim/plant/exponential.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "boards/sim/plant/phi_chain.hpp"

namespace hmp::sim::plant {

namespace {

using Vector = std::array<double, kMaxState>;

// Points along a step at which the switch functions are predicted (2^kCheckpointLevel of them); a step
// over which the piece changes is taken as that many sub-steps, one in which a switch falls as
// 2^(kFineLevel − kCheckpointLevel) finer ones (31 µs at 1 ms: a tenth of the 10⁵ N/m strings' period).
constexpr int kCheckpointLevel = 2;
constexpr int kCheckpoints = 1 << kCheckpointLevel;
constexpr int kFineLevel = 5;
constexpr int kLevels = kFineLevel + 1;
// Linearisations kept: a slack/taut transient visits a handful of pieces, and a vibrating grip a few
// poses of each.
constexpr int kCacheSize = 24;
// A linearisation used this long with the state more than kSettledDrift of its reach away is taken again.
constexpr double kSettledDrift = 0.1;  // of the reach (linearisation_drift() = 1)
constexpr double kSettleTime = 20e-3;  // s

// The matrix functions of one piece, linearised at `origin`.
struct Linearisation {
  bool valid = false;
  std::uint32_t piece = 0;
  double h = 0;
  int n = 0, switches = 0;
  std::uint64_t last_use = 0;
  double offset_for = 0;  // s it has been used with the state more than kSettledDrift away
  Vector origin{};
  PhiChain chain{kLevels};
  // rows[j]: the switch functions' gradient times P(t_j), t_j = (j + 1)·h / kCheckpoints: g(t_j) ≈ g(0) +
  // rows[j]·f(y(0)) along the piece's linear motion.
  std::vector<double> rows = std::vector<double>(static_cast<std::size_t>(kCheckpoints) * kMaxSwitches * kMaxState);
};

class Exponential final : public Integrator {
 public:
  Exponential()
      : cache_(kCacheSize), jacobian_(kMaxState * kMaxState), gradient_(kMaxSwitches * kMaxState),
        q_(kMaxSwitches * kMaxState), tmp_(kMaxSwitches * kMaxState) {}
  Method method() const override { return Method::exponential; }
  void invalidate() override {
    for (Linearisation& l : cache_) l.valid = false;
  }

  void step(OdeSystem& system, double* y, double h) override {
    double g[kMaxSwitches];
    const int ng = system.switch_functions(y, g);
    const std::uint32_t piece = system.piece_of(g);
    const Linearisation& lin = linearisation(system, y, piece, h, h);
    system.derivative(y, f_.data());
    ++evaluations_;
    if (ng > 0 && switch_within(system, lin, g, piece, ng)) {
      split_step(system, y, h);
      return;
    }
    etd2(system, lin, 0, h, y);
  }

 private:
  // One ETD2 step of level `level` (length h / 2^level) from y, with f_ = f(y) on entry (Cox and
  // Matthews' ETDRK2): a = y + P·f(y); y ← a + (Q/τ)·(f(a) − E·f(y)). The second stage takes the
  // change of the nonlinear remainder f − A·y over the step as linear in time.
  void etd2(OdeSystem& system, const Linearisation& lin, int level, double h, double* y) {
    const int n = lin.n;
    const double tau = std::ldexp(h, -level);
    for (int i = 0; i < n; ++i) a_[i] = y[i];
    multiply_add(lin.chain.integral(level), f_.data(), 1.0, n, a_.data());
    system.project(a_.data());
    system.derivative(a_.data(), f1_.data());
    ++evaluations_;
    multiply_add(lin.chain.exponential(level), f_.data(), -1.0, n, f1_.data());
    for (int i = 0; i < n; ++i) y[i] = a_[i];
    multiply_add(lin.chain.ramp(level), f1_.data(), 1.0 / tau, n, y);
    system.project(y);
  }

  // out += s·(M·v), M n×n row-major.
  static void multiply_add(const double* m, const double* v, double s, int n, double* out) {
    for (int i = 0; i < n; ++i) {
      const double* row = m + i * n;
      double s0 = 0, s1 = 0;
      int j = 0;
      for (; j + 2 <= n; j += 2) {
        s0 += row[j] * v[j];
        s1 += row[j + 1] * v[j + 1];
      }
      if (j < n) s0 += row[j] * v[j];
      out[i] += s * (s0 + s1);
    }
  }

  // Whether the piece changes at any checkpoint from `first` on, predicted from the state whose switch
  // functions are g0 and derivative f_.
  bool switch_within(const OdeSystem& system, const Linearisation& lin, const double* g0, std::uint32_t piece,
                     int ng, int first = 0, int last = kCheckpoints - 1) const {
    const int n = lin.n;
    double g[kMaxSwitches];
    for (int c = first; c <= last; ++c) {
      const double* rows = &lin.rows[static_cast<std::size_t>(c) * kMaxSwitches * kMaxState];
      for (int k = 0; k < ng; ++k) {
        double s = g0[k];
        for (int j = 0; j < n; ++j) s += rows[k * n + j] * f_[j];
        g[k] = s;
      }
      if (system.piece_of(g) != piece) return true;
    }
    return false;
  }

  // A step over which the piece changes, as kCheckpoints sub-steps: one over which no switch is predicted
  // (from its start) and whose end is on its start's piece is taken whole; the others as 2^(kFineLevel −
  // kCheckpointLevel) fine sub-steps, each on the piece its start is on. f_ = f(y) on entry.
  void split_step(OdeSystem& system, double* y, double h) {
    const int n = system.size();
    double g[kMaxSwitches];
    for (int k = 0; k < kCheckpoints; ++k) {
      if (k > 0) {
        system.derivative(y, f_.data());
        ++evaluations_;
      }
      const int ng = system.switch_functions(y, g);
      const std::uint32_t piece = system.piece_of(g);
      const Linearisation* lin = &linearisation(system, y, piece, h, std::ldexp(h, -kCheckpointLevel));
      if (!switch_within(system, *lin, g, piece, ng, 0, 0)) {
        for (int i = 0; i < n; ++i) saved_[i] = y[i];
        const Vector f_saved = f_;
        etd2(system, *lin, kCheckpointLevel, h, y);
        system.switch_functions(y, g);
        if (system.piece_of(g) == piece) continue;
        for (int i = 0; i < n; ++i) y[i] = saved_[i];
        f_ = f_saved;
      }
      for (int m = 0; m < (1 << (kFineLevel - kCheckpointLevel)); ++m) {
        if (m > 0) {
          system.derivative(y, f_.data());
          ++evaluations_;
        }
        system.switch_functions(y, g);
        etd2(system, linearisation(system, y, system.piece_of(g), h, std::ldexp(h, -kFineLevel)), kFineLevel, h, y);
      }
    }
  }

  // The cached linearisation of `piece` at step h taken nearest to y, if y is within its reach.
  Linearisation* find(const OdeSystem& system, const double* y, std::uint32_t piece, double h, double* drift) {
    Linearisation* nearest = nullptr;
    double best = 1.0;
    for (Linearisation& l : cache_) {
      if (!l.valid || l.piece != piece || l.h != h || l.n != system.size()) continue;
      const double d = system.linearisation_drift(l.origin.data(), y);
      if (d <= best) {
        best = d;
        nearest = &l;
      }
    }
    if (nearest != nullptr) nearest->last_use = ++clock_;
    if (drift != nullptr) *drift = best;
    return nearest;
  }

  // The linearisation for the next `span` of simulated time: the cached one, else a new one in place of
  // the least recently used. A grip that has settled away from where its linearisation was taken
  // (gravity sagging it onto the finger, a vibration's mean shifting) is linearised again where it now
  // is, once it has stayed more than kSettledDrift of the reach away for kSettleTime: a stale
  // linearisation's error grows with the offset (0.07 mm of sag cost 0.9 % of finger force at 10⁵ N/m),
  // and an offset that persists is worth one recompute.
  const Linearisation& linearisation(OdeSystem& system, const double* y, std::uint32_t piece, double h,
                                     double span) {
    double drift = 0;
    Linearisation* lin = find(system, y, piece, h, &drift);
    if (lin != nullptr) {
      lin->offset_for = drift > kSettledDrift ? lin->offset_for + span : 0.0;
      if (lin->offset_for > kSettleTime) recompute(system, y, piece, h, *lin);
    }
    if (lin == nullptr) {
      lin = &cache_[0];
      for (Linearisation& l : cache_)
        if (!l.valid || (lin->valid && l.last_use < lin->last_use)) lin = &l;
      recompute(system, y, piece, h, *lin);
      lin->last_use = ++clock_;
    }
    return *lin;
  }

  void recompute(OdeSystem& system, const double* y, std::uint32_t piece, double h, Linearisation& l) {
    const int n = system.size();
    l.valid = true;
    l.offset_for = 0;
    l.piece = piece;
    l.h = h;
    l.n = n;
    for (int i = 0; i < n; ++i) l.origin[i] = y[i];
    // The piece's Jacobian and the switch functions' gradient by forward differences (√ε steps).
    double g0[kMaxSwitches], g1[kMaxSwitches];
    const int ng = system.switch_functions(y, g0);
    l.switches = ng;
    system.piece_derivative(y, piece, f0_.data());
    for (int i = 0; i < n; ++i) tmp_y_[i] = y[i];
    for (int j = 0; j < n; ++j) {
      const double delta = 1.5e-8 * std::fmax(std::fabs(y[j]), system.scale(j));
      tmp_y_[j] = y[j] + delta;
      system.piece_derivative(tmp_y_.data(), piece, col_.data());
      if (ng > 0) system.switch_functions(tmp_y_.data(), g1);
      tmp_y_[j] = y[j];
      for (int i = 0; i < n; ++i) jacobian_[static_cast<std::size_t>(i * n + j)] = (col_[i] - f0_[i]) / delta;
      for (int k = 0; k < ng; ++k) gradient_[static_cast<std::size_t>(k * n + j)] = (g1[k] - g0[k]) / delta;
    }
    evaluations_ += static_cast<std::uint64_t>(n + 1);
    l.chain.compute(jacobian_.data(), n, h, kLevels);
    ++factorisations_;
    if (ng == 0) return;
    // rows[c] = G·P(t_c) by t_{c+1} = t_c + τ: G·P(t + τ) = G·P(t) + (G·E(t))·P(τ), G·E(t + τ) = (G·E(t))·E(τ).
    const double* e_tau = l.chain.exponential(kCheckpointLevel);
    const double* p_tau = l.chain.integral(kCheckpointLevel);
    const int m = ng * n;
    for (int i = 0; i < m; ++i) q_[static_cast<std::size_t>(i)] = gradient_[static_cast<std::size_t>(i)];
    for (int c = 0; c < kCheckpoints; ++c) {
      double* rows = &l.rows[static_cast<std::size_t>(c) * kMaxSwitches * kMaxState];
      multiply_rows(q_.data(), ng, p_tau, rows, n);
      if (c > 0) {
        const double* before = rows - kMaxSwitches * kMaxState;
        for (int i = 0; i < m; ++i) rows[i] += before[i];
      }
      multiply_rows(q_.data(), ng, e_tau, tmp_.data(), n);
      for (int i = 0; i < m; ++i) q_[static_cast<std::size_t>(i)] = tmp_[static_cast<std::size_t>(i)];
    }
  }

  std::vector<Linearisation> cache_;
  std::uint64_t clock_ = 0;
  std::vector<double> jacobian_, gradient_, q_, tmp_;
  Vector f_{}, f1_{}, a_{}, f0_{}, col_{}, tmp_y_{}, saved_{};
};

}  // namespace

std::unique_ptr<Integrator> make_exponential_integrator() { return std::make_unique<Exponential>(); }

}  // namespace hmp::sim::plant
