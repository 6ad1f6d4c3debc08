#include "boards/sim/plant/exponential.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
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
// A fine sub-step on a piece that has no linearisation within reach is taken as classical Runge–Kutta
// sub-steps, each at most kExplicitReach / ‖A‖₁ long (A the balanced Jacobian of the quarter's piece, whose
// 1-norm bounds the fastest mode's rate): a piece a string snaps through once is seldom visited again at
// the same pose, and a linearisation costs as much as ~100 derivatives. One sub-step of 31 µs at 10⁵ N/m
// (‖τA‖₁ ≈ 0.4) cost 3.2 % of the slack scene's string force against 1.7 % on linearisations; two cost
// 1.8 %. Where more than kExplicitParts would be needed (10⁷ N/m) the piece is linearised.
constexpr double kExplicitReach = 0.25;
constexpr int kExplicitParts = 8;
// A checkpoint sub-step on a piece with no linearisation within reach is taken as fine sub-steps until
// the piece has been missed this many times near the same state, then linearised (a carried grip's
// pieces are passed by; a held grip's come back).
constexpr int kMissesToLinearise = 2;
// Linearisations kept: a slack/taut transient visits a handful of pieces, and a vibrating grip a few
// poses of each.
constexpr int kCacheSize = 24;
// A linearisation whose state's drift, averaged over kSettleTime, exceeds kSettledDrift is taken again.
constexpr double kSettledDrift = 0.1;  // of the reach (a drift of length 1)
constexpr double kSettleTime = 20e-3;  // s
// A whole step's new linearisation is taken ahead of its start along the last step's motion, by the
// system's linearisation_lead() but at most kStepsAhead such steps ahead: it serves states within reach
// on every side, and a state moving on (a carried grip) then finds it over 1 + lead of the reach instead
// of 1. A start that moved less than kLeastMotion of the reach in a step (a vibrating grip) is taken as
// not moving.
constexpr double kStepsAhead = 4;
constexpr double kLeastMotion = 0.05;
// A whole step that finds no linearisation within reach while the state is carried on steadily (its
// start moved, over the last kSteadySteps whole steps, at least kSteadiness of kSteadySteps times its
// last step's motion: a vibration turns back within its period, a carried grip does not) is taken as
// classical Runge–Kutta parts of at most kCarriedReach / rate each, located at switches, instead of on
// a new linearisation. The rate: the larger of ‖A‖₁ of the last whole step's linearisation and the
// system's bound on its switch frequency (a string snapping taut on the way brings that rate, a piece
// with it slack lacks it). A grip carried at 0.2 mm/ms passes a linearisation's reach in 2–3 steps,
// and a linearisation costs as much as some 300 derivatives (53 µs): carried to the frame's corner at
// 10⁵ N/m, 0.63% / 0.21% of string / finger force became 0.47% / 0.08% at 1.7 times the speed. Only
// where the parts sample the strings' ringing (the switch frequency turns at most kNyquistTurn between
// checkpoints, 10³–10⁵ N/m); above, the ringing needs the followed steps below.
constexpr int kSteadySteps = 6;
constexpr double kSteadiness = 0.75;
constexpr double kCarriedReach = 1.0;
// A whole step whose end has drifted more than this from its start is taken again on a linearisation at
// its midpoint (a grip being carried; a vibrating one moves less in a step: 1.3 at 50 Hz, 10⁷ N/m).
constexpr double kFarStep = 2.0;
// A whole step whose second-stage correction exceeds this (of a state's scale) is taken again as two halves.
constexpr double kCorrectionLimit = 0.01;
// The checkpoints see a switch only where a switch function is on the other side at one of them. Where
// the system's switch_frequency() turns more than π between two checkpoints (they sample it below its
// Nyquist rate) a switch function can cross zero and come back between them: at 10⁶ N/m a string near
// slack rings at ~2.4 kHz and goes slack for less than the 250 µs between checkpoints; the whole steps
// and quarters that missed it were 34% off in string force over one tick. There, if the fine sub-steps
// do sample it (turn at most π each), a (sub-)step is also followed along its piece's linear motion to
// every fine sub-step's end. Wherever the fine sub-steps sample it, a fine sub-step whose end is on
// another piece is taken again by Runge–Kutta to the switch and on from it. A kink inside a 31 µs ETD2
// step on the old piece cost more than the missed switches at 10⁶ N/m; at 10⁵ N/m, where the corner's
// strings snap at 250 Hz, it cost 0.92% of the carried grip's string force against 0.63% located (the
// 250 Hz, 1 N vibration 0.44% against 0.08%, the slack scene 1.57% against 1.00%), for 20–30% more
// CPU time where strings snap. The bound on the plant's rate turns, between checkpoints, 2.7 rad at
// 10⁵ N/m, 8.4 at 10⁶ and 27 at 10⁷ (3.3 between fine sub-steps: there neither would see it).
constexpr double kNyquistTurn = std::numbers::pi;
// A located or followed fine sub-step's Runge–Kutta parts each turn the switch frequency by at most
// kPartTurn (one part at least): the rate after a switch, not the piece's before it (a string snapping
// taut makes it faster), sets their accuracy; classical Runge–Kutta's phase error is turn⁵/120 a part.
constexpr double kPartTurn = 0.35;
// A switch is located to this fraction of the (sub-)step it falls in: Newton's method on its cubic stops
// there (a 31 µs fine sub-step: 3 × 10⁻¹⁷ s).
constexpr double kSwitchTolerance = 1e-12;

// The matrix functions of one piece, linearised at `origin`.
struct Linearisation {
  explicit Linearisation(PhiChain::Workspace& work)
      : chain(kLevels, 1u | 1u << 1 | 1u << kCheckpointLevel | 1u << kFineLevel, &work) {}
  bool valid = false;
  std::uint32_t piece = 0;
  double h = 0;
  int n = 0, switches = 0;
  std::uint64_t last_use = 0;
  // The drift of the state it has been used at, averaged over the last kSettleTime of simulated time.
  std::array<double, kMaxDrift> mean_drift{};
  double settled_for = 0;  // s of whole steps in a row on it
  Vector origin{};
  // The levels a step reads: h, its halves (a step taken again as two), its quarters (a split step's
  // checkpoint sub-steps) and the fine sub-steps around a switch.
  PhiChain chain;
  // rows[j]: the switch functions' gradient times P(t_j), t_j = (j + 1)·h / kCheckpoints: g(t_j) ≈ g(0) +
  // rows[j]·f(y(0)) along the piece's linear motion.
  std::vector<double> rows = std::vector<double>(static_cast<std::size_t>(kCheckpoints) * kMaxSwitches * kMaxState);
  // The switch functions' gradient G by its nonzeros: g(y) ≈ g(y₀) + G·(y − y₀).
  SparseRows gradient;
};

// A system seen in its linear coordinates (OdeSystem::to_linear): what the steps work on when it has them.
class InLinearCoordinates final : public OdeSystem {
 public:
  void bind(OdeSystem& system) { s_ = &system; }
  int size() const override { return s_->size(); }
  int coupled_size() const override { return s_->coupled_size(); }
  // The system's rates are computed in dzdt and turned into the coordinates' rates in place.
  void derivative(const double* z, double* dzdt) override {
    s_->from_linear(z, y_.data());
    s_->derivative(y_.data(), dzdt);
    s_->linear_rates(y_.data(), dzdt, dzdt);
  }
  void piece_derivative(const double* z, std::uint32_t piece, double* dzdt) override {
    s_->from_linear(z, y_.data());
    s_->piece_derivative(y_.data(), piece, dzdt);
    s_->linear_rates(y_.data(), dzdt, dzdt);
  }
  void position_rates(const double* z, double* dzdt) const override {
    s_->from_linear(z, y_.data());
    s_->derivative(y_.data(), f_.data());
    s_->linear_rates(y_.data(), f_.data(), f_.data());
    for (int i = 0; i < size(); ++i)
      if (is_position(i)) dzdt[i] = f_[static_cast<std::size_t>(i)];
  }
  bool is_position(int index) const override { return s_->is_position(index); }
  double scale(int index) const override { return s_->linear_scale(index); }
  void project(double* z) const override { s_->project(z); }
  int switch_functions(const double* z, double* g) const override {
    s_->from_linear(z, y_.data());
    return s_->switch_functions(y_.data(), g);
  }
  std::uint32_t piece_of(const double* g) const override { return s_->piece_of(g); }
  int linearisation_drift(const double* origin, const double* z, double* drift, double beyond) const override {
    return s_->linearisation_drift(origin, z, drift, beyond);
  }
  double linearisation_lead() const override { return s_->linearisation_lead(); }
  double switch_frequency() const override { return s_->switch_frequency(); }

 private:
  OdeSystem* s_ = nullptr;
  mutable std::array<double, kMaxState> y_{}, f_{};
};

class Exponential final : public Integrator {
 public:
  Exponential() : jacobian_(kMaxState * kMaxState), gradient_(kMaxSwitches * kMaxState) {
    cache_.reserve(kCacheSize);
    for (int i = 0; i < kCacheSize; ++i) cache_.emplace_back(work_);
  }
  Method method() const override { return Method::exponential; }
  void invalidate() override {
    for (Linearisation& l : cache_) l.valid = false;
    for (Miss& m : misses_) m.count = 0;
    stepping_ = nullptr;
    carrying_ = false;
    run_ = 0;
    whole_norm_ = 0;
  }

  void step(OdeSystem& system, double* y, double h) override {
    if (!system.has_linear_coordinates()) {
      advance(system, y, h);
      return;
    }
    linear_.bind(system);
    system.to_linear(y, z_.data());
    advance(linear_, z_.data(), h);
    system.from_linear(z_.data(), y);
  }

 private:
  void advance(OdeSystem& system, double* y, double h) {
    remember_start(y, h, system.size());
    // The derivative first: the switch functions at the same state then come with it (PlantDynamics).
    system.derivative(y, f_.data());
    ++evaluations_;
    double g[kMaxSwitches];
    const int ng = system.switch_functions(y, g);
    const std::uint32_t piece = system.piece_of(g);
    const int n = system.size();
    std::array<double, kMaxDrift> d{};
    // A grip being carried (the last whole step went far): this step's midpoint is predicted from the
    // last step's motion and linearised directly, without a linearisation at the start that the
    // midpoint rule below would replace.
    const double turn = std::ldexp(h, -kCheckpointLevel) * system.switch_frequency();  // between checkpoints
    Linearisation* lin = nullptr;
    const bool predicted = carrying_;
    if (predicted) {
      // saved_ still holds the last whole step's start: nothing has been saved since.
      along_motion(system, saved_.data(), y, 0.5, mid_.data());
      lin = &find_or_new(system, mid_.data(), piece, h);
      stepping_ = nullptr;
    } else {
      const bool may_go_without = turn <= kNyquistTurn && whole_norm_ > 0 && carried_on(system, y);
      lin = linearisation(system, y, piece, h, may_go_without);
      if (lin == nullptr) {
        const double rate = std::fmax(whole_norm_, system.switch_frequency());
        runge_kutta(system, y, h, static_cast<int>(std::ceil(h * rate / kCarriedReach)), true);
        return;
      }
    }
    whole_norm_ = lin->chain.norm();
    carrying_ = false;
    const double fine_turn = std::ldexp(turn, kCheckpointLevel - kFineLevel);
    locate_ = fine_turn <= kNyquistTurn;
    follow_ = turn > kNyquistTurn && locate_;
    followed_parts_ = std::max(1, static_cast<int>(std::ceil(fine_turn / kPartTurn)));
    if (ng > 0 &&
        (switch_within(system, *lin, g, piece, ng) || (follow_ && switch_along(system, *lin, 0, g, piece, ng)))) {
      split_step(system, y, h, lin->chain.norm());
      return;
    }
    save_start(y, n);
    etd2(system, *lin, 0, h, y);
    // A step that carried the state far (a grip the finger moves) is taken again on a linearisation at its
    // midpoint: the remainder's change is then symmetric about the step's middle, and its linear part is
    // what ETD2 takes exactly. A step on a predicted midpoint is taken again only if the prediction missed
    // by more than the reach.
    const bool far = drift_squared(system, saved_.data(), y, d) > kFarStep * kFarStep;
    if (far || predicted) {
      for (int i = 0; i < n; ++i) mid_[i] = 0.5 * (saved_[i] + y[i]);
      system.project(mid_.data());
      if (!predicted || drift_squared(system, lin->origin.data(), mid_.data(), d) > 1.0) {
        restore_start(y, n);
        lin = &find_or_new(system, mid_.data(), piece, h);
        etd2(system, *lin, 0, h, y);
      }
    }
    if (far) {
      carrying_ = true;
      return;
    }
    // The second stage's correction y − a is the remainder's change over the step: where it is more than
    // kCorrectionLimit of a state's scale the step crossed something its start did not see (a string going
    // slack between the switch checkpoints, the 10⁵ N/m strings ringing at 710 Hz through the step), and
    // it is taken again as two halves. Not after the midpoint rule: a carried grip's stiff strings ring
    // at kilohertz, where half steps are no better than whole ones (27 % against 9 % of string force).
    if (correction(system, y) > kCorrectionLimit) {
      restore_start(y, n);
      etd2(system, *lin, 1, h, y);
      system.derivative(y, f_.data());
      ++evaluations_;
      etd2(system, *lin, 1, h, y);
    }
  }

  // One ETD2 step of level `level` (length h / 2^level) from y, with f_ = f(y) on entry (Cox and
  // Matthews' ETDRK2): a = y + P·f(y); y ← a + (Q/τ)·(f(a) − E·f(y)). The second stage takes the
  // change of the nonlinear remainder f − A·y over the step as linear in time.
  void etd2(OdeSystem& system, Linearisation& lin, int level, double h, double* y) {
    const int n = lin.n, ld = PhiChain::stride(n);
    const double tau = std::ldexp(h, -level);
    for (int i = 0; i < n; ++i) a_[i] = y[i];
    multiply_add_columns(lin.chain.integral(level), n, ld, f_.data(), 1.0, a_.data());
    system.project(a_.data());
    system.derivative(a_.data(), f1_.data());
    ++evaluations_;
    multiply_add_columns(lin.chain.exponential(level), n, ld, f_.data(), -1.0, f1_.data());
    for (int i = 0; i < n; ++i) y[i] = a_[i];
    multiply_add_columns(lin.chain.ramp(level), n, ld, f1_.data(), 1.0 / tau, y);
    system.project(y);
  }

  // A (sub-)step's start, state and derivative, kept so that the step can be taken again.
  void save_start(const double* y, int n) {
    for (int i = 0; i < n; ++i) saved_[i] = y[i];
    f_saved_ = f_;
  }
  void restore_start(double* y, int n) {
    for (int i = 0; i < n; ++i) y[i] = saved_[i];
    f_ = f_saved_;
  }

  // The largest |y − a| over each coupled state's scale, y the end of the last etd2() and a its first stage.
  double correction(const OdeSystem& system, const double* y) const {
    double largest = 0;
    for (int i = 0; i < system.coupled_size(); ++i)
      largest = std::fmax(largest, std::fabs(y[i] - a_[i]) / system.scale(i));
    return largest;
  }

  // Whether the piece changes at any checkpoint from `first` on, predicted from the state whose switch
  // functions are g0 and derivative f_.
  bool switch_within(const OdeSystem& system, const Linearisation& lin, const double* g0, std::uint32_t piece, int ng,
                     int first = 0, int last = kCheckpoints - 1) const {
    const int n = lin.n;
    double g[kMaxSwitches];
    for (int c = first; c <= last; ++c) {
      const double* rows = &lin.rows[static_cast<std::size_t>(c) * kMaxSwitches * kMaxState];
      for (int k = 0; k < ng; ++k) g[k] = g0[k];
      multiply_add_rows(rows, ng, n, f_.data(), 1.0, g);
      if (system.piece_of(g) != piece) return true;
    }
    return false;
  }

  // Whether the piece changes at the end of any fine sub-step of a (sub-)step of `level` from the state
  // whose switch functions are g0 and derivative f_, predicted along the linearisation's motion:
  // y(t + τ) = y(t) + P(τ)·y'(t), y'(t + τ) = E(τ)·y'(t), τ the fine level's step, g ≈ g0 + G·(y − y0).
  bool switch_along(const OdeSystem& system, Linearisation& lin, int level, const double* g0, std::uint32_t piece,
                    int ng) {
    // The motion from y, d(t) = y(t) − y, moves by d(t + τ) = E(τ)·d(t) + P(τ)·f(y).
    const int n = lin.n, ld = PhiChain::stride(n);
    const double* e = lin.chain.exponential(kFineLevel);
    for (int i = 0; i < n; ++i) push_[i] = 0;
    multiply_add_columns(lin.chain.integral(kFineLevel), n, ld, f_.data(), 1.0, push_.data());
    moved_ = push_;
    double g[kMaxSwitches];
    for (int j = 1;; ++j) {
      gradient_times(lin, moved_.data(), 1.0, g);
      for (int k = 0; k < ng; ++k) g[k] += g0[k];
      if (system.piece_of(g) != piece) return true;
      if (j == 1 << (kFineLevel - level)) return false;
      next_ = push_;
      multiply_add_columns(e, n, ld, moved_.data(), 1.0, next_.data());
      moved_.swap(next_);
    }
  }

  // A step over which the piece changes, as kCheckpoints sub-steps: one over which no switch is predicted
  // (from its start) and whose end is on its start's piece is taken whole; the others as 2^(kFineLevel −
  // kCheckpointLevel) fine sub-steps, each on the piece its start is on. So is one on a piece that
  // sub_step_linearisation() gives no linearisation for. f_ = f(y) on entry; `norm`: ‖A‖₁ of the whole
  // step's piece.
  void split_step(OdeSystem& system, double* y, double h, double norm) {
    const int n = system.size();
    double g[kMaxSwitches];
    for (int k = 0; k < kCheckpoints; ++k) {
      if (k > 0) {
        system.derivative(y, f_.data());
        ++evaluations_;
      }
      const int ng = system.switch_functions(y, g);
      const std::uint32_t piece = system.piece_of(g);
      Linearisation* lin = sub_step_linearisation(system, y, piece, h, SubStep::checkpoint, explicit_parts(h, norm));
      if (lin != nullptr && !switch_within(system, *lin, g, piece, ng, 0, 0) &&
          !(follow_ && switch_along(system, *lin, kCheckpointLevel, g, piece, ng))) {
        save_start(y, n);
        etd2(system, *lin, kCheckpointLevel, h, y);
        system.switch_functions(y, g);
        if (system.piece_of(g) == piece) continue;
        restore_start(y, n);
      }
      // The fastest rate is bounded by ‖A‖₁ of this quarter's piece (or the step's), taken as the bound
      // of the fine sub-steps' pieces too. They differ from it in the strings that switch within the
      // quarter, whose tension is small near the switch.
      const int parts = explicit_parts(h, lin != nullptr ? lin->chain.norm() : norm);
      bool current = true;  // f_ = f(y)
      for (int m = 0; m < (1 << (kFineLevel - kCheckpointLevel)); ++m) {
        if (!current) {
          system.derivative(y, f_.data());
          ++evaluations_;
        }
        current = fine_substep(system, y, h, parts);
      }
    }
  }

  // The Runge–Kutta parts of a fine sub-step of a step h on a piece whose ‖A‖₁ is `norm`.
  static int explicit_parts(double h, double norm) {
    return static_cast<int>(std::ceil(std::ldexp(h, -kFineLevel) * norm / kExplicitReach));
  }

  // Sub-steps that may go without a linearisation of their piece.
  enum class SubStep { checkpoint, fine };

  // The linearisation a sub-step from y on `piece` is taken on: the cached one within reach; else a new
  // one, or none (nullptr) where the sub-step goes without. A fine sub-step goes without if its
  // Runge–Kutta `parts` are at most kExplicitParts; a checkpoint quarter then too (to its fine sub-steps),
  // until its piece has been missed kMissesToLinearise times near y. (A whole step goes without only
  // where the state is carried on steadily: linearisation(); a predicted one never: find_or_new().)
  Linearisation* sub_step_linearisation(OdeSystem& system, const double* y, std::uint32_t piece, double h,
                                        SubStep sub_step, int parts) {
    if (Linearisation* cached = find(system, y, piece, h)) return cached;
    const bool linearise =
        parts > kExplicitParts || (sub_step == SubStep::checkpoint && missed_enough(system, y, piece, h));
    return linearise ? &new_linearisation(system, y, piece, h) : nullptr;
  }

  // One fine sub-step (h / 2^kFineLevel) from y, with f_ = f(y) on entry, on the piece y is on: by its
  // linearisation, or as `parts` Runge–Kutta steps where sub_step_linearisation() gives none.
  // Returns whether f_ is f(y) at the end.
  bool fine_substep(OdeSystem& system, double* y, double h, int parts) {
    const double fine = std::ldexp(h, -kFineLevel);
    double g[kMaxSwitches], end[kMaxSwitches];
    const int ng = system.switch_functions(y, g);
    const std::uint32_t piece = system.piece_of(g);
    Linearisation* on = sub_step_linearisation(system, y, piece, h, SubStep::fine, parts);
    if (on == nullptr) return runge_kutta(system, y, fine, follow_ ? followed_parts_ : parts, locate_);
    if (!locate_) {
      etd2(system, *on, kFineLevel, h, y);
      return false;
    }
    save_start(y, system.size());
    etd2(system, *on, kFineLevel, h, y);
    system.switch_functions(y, end);
    if (system.piece_of(end) == piece) return false;
    // Taken again by Runge–Kutta up to the switch and on from it: the right-hand side's kink then falls
    // between two parts, not inside one.
    restore_start(y, system.size());
    // The switch functions' rates at both ends along the piece's linear motion, ẏ(τ) = E(τ)·f(y), over
    // the sub-step: the crossing is found on the cubic they and the values make.
    double rate[kMaxSwitches], end_rate[kMaxSwitches];
    const int n = system.size(), ld = PhiChain::stride(n);
    for (int i = 0; i < n; ++i) next_[i] = 0;
    multiply_add_columns(on->chain.exponential(kFineLevel), n, ld, f_.data(), 1.0, next_.data());
    gradient_times(*on, f_.data(), fine, rate);
    gradient_times(*on, next_.data(), fine, end_rate);
    const double at = switch_time(system, ng, piece, g, end, rate, end_rate);
    runge_kutta(system, y, at * fine, static_cast<int>(std::ceil(at * followed_parts_)));
    system.derivative(y, f_.data());
    ++evaluations_;
    runge_kutta(system, y, (1 - at) * fine, static_cast<int>(std::ceil((1 - at) * followed_parts_)));
    return false;
  }

  // `parts` classical Runge–Kutta steps over `length` from y, with f_ = f(y) on entry. `locate`: a part
  // over which the piece changes is taken again as two, split where the switch functions, taken as linear
  // over the part, say it changed. Returns whether f_ is f(y) at the end (so it is where it located).
  bool runge_kutta(OdeSystem& system, double* y, double length, int parts, bool locate = false) {
    const int n = system.size();
    double g[kMaxSwitches], end[kMaxSwitches], slope[kMaxSwitches];
    const int ng = locate ? system.switch_functions(y, g) : 0;
    const double tau = length / parts;
    for (int part = 0; part < parts; ++part) {
      if (part > 0 && ng == 0) {
        system.derivative(y, f_.data());
        ++evaluations_;
      }
      if (ng > 0) save_start(y, n);
      rk4_step(system, y, tau, f_.data(), runge_kutta_);
      evaluations_ += 3;
      if (ng == 0) continue;
      // The derivative first: the switch functions at the same state come with it.
      system.derivative(y, f_.data());
      ++evaluations_;
      system.switch_functions(y, end);
      const std::uint32_t piece = system.piece_of(g);
      if (system.piece_of(end) != piece) {
        restore_start(y, n);
        for (int k = 0; k < ng; ++k) slope[k] = end[k] - g[k];
        const double at = switch_time(system, ng, piece, g, end, slope, slope);
        rk4_step(system, y, at * tau, f_.data(), runge_kutta_);
        system.derivative(y, f_.data());
        rk4_step(system, y, (1 - at) * tau, f_.data(), runge_kutta_);
        system.derivative(y, f_.data());
        evaluations_ += 8;
        system.switch_functions(y, end);
      }
      for (int k = 0; k < ng; ++k) g[k] = end[k];
    }
    return ng > 0;
  }

  // out = scale·G·v for the linearisation's switch gradient G.
  static void gradient_times(const Linearisation& lin, const double* v, double scale, double* out) {
    const SparseRows& g = lin.gradient;
    for (int k = 0; k < g.rows; ++k) {
      double sum = 0;
      for (int l = g.first(k); l < g.last(k); ++l) sum += g.value(k, l) * v[g.column(l)];
      out[k] = scale * sum;
    }
  }

  // Where, as a fraction of a sub-step, the piece first changes (at its end it is not `piece`): the
  // switch functions as the cubics with values g0, g1 and rates m0, m1 (per sub-step) at its ends.
  static double switch_time(const OdeSystem& system, int ng, std::uint32_t piece, const double* g0, const double* g1,
                            const double* m0, const double* m1) {
    const auto cubic = [&](int k, double s) {
      const double s2 = s * s, s3 = s2 * s;
      return (2 * s3 - 3 * s2 + 1) * g0[k] + (s3 - 2 * s2 + s) * m0[k] + (3 * s2 - 2 * s3) * g1[k] + (s3 - s2) * m1[k];
    };
    double at = 1, g[kMaxSwitches];
    for (int k = 0; k < ng; ++k) {
      if ((g0[k] > 0) == (g1[k] > 0)) continue;
      // Newton's method on the cubic from the secant's zero, kept inside the bracket [lo, hi] (bisecting
      // where it would leave it), until its step is below kSwitchTolerance. Where the rates are the
      // secant's own the cubic is that line, and its zero is found at once.
      double lo = 0, hi = 1, s = g0[k] / (g0[k] - g1[k]);
      for (int i = 0; i < 40 && hi - lo > kSwitchTolerance; ++i) {
        const double value = cubic(k, s);
        if (value == 0) break;
        ((value > 0) == (g0[k] > 0) ? lo : hi) = s;
        const double s2 = s * s;
        const double slope =
            (6 * s2 - 6 * s) * (g0[k] - g1[k]) + (3 * s2 - 4 * s + 1) * m0[k] + (3 * s2 - 2 * s) * m1[k];
        const double newton = s - value / slope;
        const double next = newton >= lo && newton <= hi ? newton : 0.5 * (lo + hi);
        const bool converged = std::fabs(next - s) <= kSwitchTolerance;
        s = next;
        if (converged) break;
      }
      if (s >= at) continue;
      // The piece just after this zero; a zero of a switch function that leaves the piece as it is (the
      // spring force of a slack string) is not the switch.
      const double after = std::fmin(1.0, s + 1e-9);
      for (int j = 0; j < ng; ++j) g[j] = cubic(j, after);
      if (system.piece_of(g) != piece) at = s;
    }
    return at;
  }

  // Whether `piece` has been missed (no linearisation within reach) kMissesToLinearise times within reach
  // of where it was first missed, this time included; the misses remembered are forgotten then.
  bool missed_enough(const OdeSystem& system, const double* y, std::uint32_t piece, double h) {
    std::array<double, kMaxDrift> d{};
    Miss* oldest = &misses_[0];
    for (Miss& m : misses_) {
      if (m.count > 0 && m.piece == piece && m.h == h && m.n == system.size() &&
          drift_squared(system, m.origin.data(), y, d, 1.0) <= 1.0) {
        m.last = ++clock_;
        if (++m.count < kMissesToLinearise) return false;
        m.count = 0;
        return true;
      }
      if (m.count == 0 || (oldest->count > 0 && m.last < oldest->last)) oldest = &m;
    }
    oldest->piece = piece;
    oldest->h = h;
    oldest->n = system.size();
    oldest->count = 1;
    oldest->last = ++clock_;
    for (int i = 0; i < system.size(); ++i) oldest->origin[i] = y[i];
    return kMissesToLinearise <= 1;
  }

  // The cached linearisation of `piece` at step h taken nearest to y, if y is within its reach; `drift`
  // receives y's drift from it.
  Linearisation* find(const OdeSystem& system, const double* y, std::uint32_t piece, double h,
                      std::array<double, kMaxDrift>& drift) {
    Linearisation* nearest = nullptr;
    double best = 1.0;
    std::array<double, kMaxDrift> d{};
    for (Linearisation& l : cache_) {
      if (!l.valid || l.piece != piece || l.h != h || l.n != system.size()) continue;
      const double d2 = drift_squared(system, l.origin.data(), y, d, best);
      if (d2 <= best) {
        best = d2;
        nearest = &l;
        drift = d;
      }
    }
    if (nearest != nullptr) nearest->last_use = ++clock_;
    return nearest;
  }
  Linearisation* find(const OdeSystem& system, const double* y, std::uint32_t piece, double h) {
    std::array<double, kMaxDrift> drift{};
    return find(system, y, piece, h, drift);
  }

  // The linearisation for a whole step: the cached one, else none (nullptr) if the step `may_go_without`
  // one (kSteadySteps), else a new one in place of the least recently used. A grip that has settled away
  // from where its linearisation was taken (gravity sagging it onto the finger, a vibration's mean
  // shifting) is linearised again where it now is, once its drift averaged over kSettleTime of whole
  // steps on that linearisation is more than kSettledDrift of the reach: a stale linearisation's error
  // grows with the offset (0.07 mm of sag cost 0.9 % of finger force at 10⁵ N/m). A grip swinging across
  // several cached linearisations uses each only briefly, and its average starts again each time.
  Linearisation* linearisation(OdeSystem& system, const double* y, std::uint32_t piece, double h, bool may_go_without) {
    std::array<double, kMaxDrift> drift{};
    Linearisation* lin = find(system, y, piece, h, drift);
    if (lin == nullptr && may_go_without) {
      stepping_ = nullptr;
      return nullptr;
    }
    if (lin != nullptr) {
      if (lin != stepping_) {
        lin->mean_drift = drift;
        lin->settled_for = 0;
      }
      const double alpha = std::fmin(1.0, h / kSettleTime);
      double m2 = 0;
      for (int i = 0; i < kMaxDrift; ++i) {
        lin->mean_drift[i] += alpha * (drift[i] - lin->mean_drift[i]);
        m2 += lin->mean_drift[i] * lin->mean_drift[i];
      }
      lin->settled_for += h;
      if (lin->settled_for >= kSettleTime && m2 > kSettledDrift * kSettledDrift) recompute(system, y, piece, h, *lin);
    }
    if (lin == nullptr) lin = &new_linearisation(system, ahead(system, y), piece, h);
    stepping_ = lin;
    return lin;
  }

  // y's drift from `origin` (into `drift`) and its squared length; infinite once known to be beyond
  // `beyond` (the drift then incomplete).
  static double drift_squared(const OdeSystem& system, const double* origin, const double* y,
                              std::array<double, kMaxDrift>& drift, double beyond = OdeSystem::kNoBound) {
    const int m = system.linearisation_drift(origin, y, drift.data(), beyond);
    if (m < 0) return OdeSystem::kNoBound;
    double d2 = 0;
    for (int i = 0; i < m; ++i) d2 += drift[i] * drift[i];
    return d2;
  }

  // This whole step's start, kept with those of the steps before it for their motion.
  void remember_start(const double* y, double h, int n) {
    run_ = run_h_ == h && run_n_ == n ? std::min(run_ + 1, kKeptStarts) : 1;
    run_h_ = h;
    run_n_ = n;
    newest_ = (newest_ + 1) % kKeptStarts;
    for (int i = 0; i < n; ++i) starts_[static_cast<std::size_t>(newest_)][i] = y[i];
  }
  // The start of the whole step `back` steps before this one, if the steps since were equal steps of one
  // system; else nullptr.
  const double* start_before(int back) const {
    if (back >= run_) return nullptr;
    return starts_[static_cast<std::size_t>((newest_ + kKeptStarts - back) % kKeptStarts)].data();
  }

  // Whether the state y, at a whole step's start, is being carried on steadily (kSteadySteps).
  bool carried_on(const OdeSystem& system, const double* y) const {
    const double *last = start_before(1), *first = start_before(kSteadySteps);
    if (first == nullptr) return false;
    std::array<double, kMaxDrift> d{};
    const double step = drift_squared(system, last, y, d);
    if (!(step >= kLeastMotion * kLeastMotion)) return false;
    const double least = kSteadiness * kSteadySteps;
    return drift_squared(system, first, y, d) >= least * least * step;
  }

  // Where a whole step from y takes a new linearisation: ahead of y along the last step's motion
  // (kStepsAhead), or y itself.
  const double* ahead(const OdeSystem& system, const double* y) {
    const double lead = system.linearisation_lead();
    const double* before = start_before(1);
    if (lead <= 0 || before == nullptr) return y;
    std::array<double, kMaxDrift> d{};
    const double d2 = drift_squared(system, before, y, d, 1.0);
    if (!(d2 <= 1.0) || d2 < kLeastMotion * kLeastMotion) return y;
    along_motion(system, before, y, std::fmin(lead / std::sqrt(d2), kStepsAhead), ahead_.data());
    return ahead_.data();
  }

  // out = y + steps·(y − from), projected: the state `steps` steps further along the motion from `from` to y.
  static void along_motion(const OdeSystem& system, const double* from, const double* y, double steps, double* out) {
    for (int i = 0; i < system.size(); ++i) out[i] = y[i] + steps * (y[i] - from[i]);
    system.project(out);
  }

  // The cached linearisation of `piece` nearest y within its reach, else a new one taken at y, for a
  // carried step: its finer levels are left until a step asks for them (a grip carried on rarely comes
  // back to the same pose).
  Linearisation& find_or_new(OdeSystem& system, const double* y, std::uint32_t piece, double h) {
    Linearisation* lin = find(system, y, piece, h);
    return lin != nullptr ? *lin : new_linearisation(system, y, piece, h, 1u);
  }

  // A linearisation taken at y, in place of the least recently used one; the levels in `keep_now` are
  // written now, the others when first read.
  Linearisation& new_linearisation(OdeSystem& system, const double* y, std::uint32_t piece, double h,
                                   std::uint32_t keep_now = ~0u) {
    Linearisation* lin = &cache_[0];
    for (Linearisation& l : cache_)
      if (!l.valid || (lin->valid && l.last_use < lin->last_use)) lin = &l;
    recompute(system, y, piece, h, *lin, keep_now);
    lin->last_use = ++clock_;
    return *lin;
  }

  void recompute(OdeSystem& system, const double* y, std::uint32_t piece, double h, Linearisation& l,
                 std::uint32_t keep_now = ~0u) {
    const int n = system.size();
    l.valid = true;
    l.mean_drift.fill(0);
    l.settled_for = 0;
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
    static_assert(kCheckpointLevel == 2, "the chain's quarter rows are the four checkpoints");
    PhiChain::QuarterRows quarters;
    if (ng > 0) {
      quarters.g = gradient_.data();
      quarters.m = ng;
      for (int c = 0; c < kCheckpoints; ++c)
        quarters.out[static_cast<std::size_t>(c)] = &l.rows[static_cast<std::size_t>(c) * kMaxSwitches * kMaxState];
    }
    // rows[c] = G·P(t_c), t_c = (c + 1)·h/4. G, the switch functions' gradient, is sparse.
    l.chain.compute(jacobian_.data(), n, h, kCheckpointLevel + 1, ng > 0 ? &quarters : nullptr, keep_now);
    ++factorisations_;
    if (ng > 0) l.gradient.gather(gradient_.data(), ng, n, n);
  }

  InLinearCoordinates linear_;
  Vector z_{};
  PhiChain::Workspace work_;  // every cached chain computes in it, one at a time
  std::vector<Linearisation> cache_;
  std::uint64_t clock_ = 0;
  const Linearisation* stepping_ = nullptr;  // the one the last whole step started on
  double whole_norm_ = 0;                    // ‖A‖₁ of the last whole step's linearisation
  bool carrying_ = false;                    // the last whole step went more than kFarStep (saved_ holds its start)
  bool locate_ = false;                      // a switch in a fine sub-step is located (kNyquistTurn)
  bool follow_ = false;                      // this step is followed to every fine sub-step (kNyquistTurn)
  int followed_parts_ = 1;                   // a located or followed fine sub-step's Runge–Kutta parts (kPartTurn)
  std::vector<double> jacobian_, gradient_;
  // Pieces a split step found no linearisation for, where.
  struct Miss {
    std::uint32_t piece = 0;
    double h = 0;
    int n = 0, count = 0;  // count 0: unused
    std::uint64_t last = 0;
    Vector origin{};
  };
  std::array<Miss, kCacheSize> misses_{};
  // The starts of the last kKeptStarts whole steps, the newest at starts_[newest_]; the last run_ of them
  // are of equal steps run_h_ of a system of run_n_ states.
  static constexpr int kKeptStarts = kSteadySteps + 1;
  std::array<Vector, kKeptStarts> starts_{};
  int newest_ = 0, run_ = 0, run_n_ = 0;
  double run_h_ = 0;
  RungeKuttaWork runge_kutta_;
  Vector f_{}, f1_{}, a_{}, f0_{}, col_{}, tmp_y_{}, saved_{}, f_saved_{}, mid_{}, ahead_{};
  Vector push_{}, moved_{}, next_{};  // switch_along()'s predicted motion
};

}  // namespace

std::unique_ptr<Integrator> make_exponential_integrator() { return std::make_unique<Exponential>(); }

}  // namespace hmp::sim::plant
