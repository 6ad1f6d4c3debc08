#include "shared/spidar/tension.hpp"

#include <cmath>
#include <limits>

#include "shared/spidar/cholesky.hpp"

namespace hmp::spidar {

namespace {

using Mask = std::uint8_t;
constexpr Mask bit(int i) { return static_cast<Mask>(1u << i); }

// The QP in the form ½ tᵀH t − gᵀt over the box [lo, hi]^8.
template <class T>
struct BoxQp {
  T h[kStrings][kStrings];
  T g[kStrings];
  T lo, hi;
};

template <class T>
T clamp_to(T v, T lo, T hi) {
  return v >= lo ? (v <= hi ? v : hi) : lo;
}  // NaN → lo

// H = λt UᵀU + λr MᵀM + s I and g = λt UᵀF + λr MᵀN, with √λ folded into the vectors so each entry is one
// 6-term dot product. Returns false if anything came out non-finite.
template <class T>
bool build_qp(const StringGeometry<T>& strings, const Vec3<T>& force, const Vec3<T>& torque, const TensionParams<T>& p,
              BoxQp<T>& qp) {
  const T wt = std::sqrt(p.lambda_t), wr = std::sqrt(p.lambda_r);
  Vec3<T> a[kStrings], b[kStrings];
  for (int i = 0; i < kStrings; ++i) {
    a[i] = wt * strings.u[i];
    b[i] = wr * strings.m[i];
  }
  const Vec3<T> fw = wt * force, nw = wr * torque;
  T check = 0;
  for (int i = 0; i < kStrings; ++i) {
    qp.g[i] = dot(a[i], fw) + dot(b[i], nw);
    for (int j = i; j < kStrings; ++j) qp.h[i][j] = qp.h[j][i] = dot(a[i], a[j]) + dot(b[i], b[j]);
    qp.h[i][i] += p.regulariser;
    check += qp.g[i] + qp.h[i][i];  // NaN or ±Inf anywhere in u, m, F, N or λ shows up here
  }
  return std::isfinite(check);
}

template <class T>
T gradient(const BoxQp<T>& qp, const T (&t)[kStrings], int i) {
  T s = -qp.g[i];
  for (int j = 0; j < kStrings; ++j) s += qp.h[i][j] * t[j];
  return s;
}

// Sweep operator (Beaton) on the symmetric matrix s (full storage): sweeping string k in makes it free,
// sweeping it out makes it active again. With the free set F swept in, starting from s = H:
//   s_FF = −H_FF⁻¹,  s_AF = H_AF·H_FF⁻¹,  s_AA = H_AA − H_AF·H_FF⁻¹·H_FA.
// So one sweep (64 multiply-adds, one division) is a whole active-set change, and the quantities the
// active-set steps need — the free strings' response to a push, the active strings' multiplier rates — are
// read off row k. Fails when the pivot is not clearly positive (in) or negative (out). The fixed 8×8 loops
// beat a triangle-only update on the Cortex-M4 (fully unrolled, no index arithmetic).
template <class T>
bool sweep(T (&s)[kStrings][kStrings], int k, bool in, T tiny) {
  const T d = s[k][k];
  if (in ? !(d > tiny) : !(d < -tiny)) return false;
  const T inv = static_cast<T>(1) / d;
  T r[kStrings];
  for (int j = 0; j < kStrings; ++j) r[j] = s[k][j] * inv;
  for (int i = 0; i < kStrings; ++i) {
    const T sik = s[i][k];
    for (int j = 0; j < kStrings; ++j) s[i][j] -= sik * r[j];
  }
  const T sign = in ? static_cast<T>(1) : static_cast<T>(-1);
  for (int i = 0; i < kStrings; ++i) s[i][k] = s[k][i] = sign * r[i];
  s[k][k] = -inv;
  return true;
}

// The dual active-set method of Goldfarb & Idnani specialised to bounds. Invariant: t minimises the
// objective with the active strings held at their bounds, and every active string's multiplier is ≥ 0
// (holding it at the bound really helps). Each step picks the free string that violates its bounds most and
// pushes it to the bound along the path that keeps the invariant, releasing any active string whose
// multiplier reaches zero on the way. No cycling: each completed push strictly raises the dual objective.
// (D. Goldfarb, A. Idnani, "A numerically stable dual method for solving strictly convex quadratic
// programs", Math. Programming 27, 1983; bounds make every constraint a single coordinate.)
template <class T>
class DualActiveSet {
 public:
  enum class Outcome { optimal, out_of_budget, singular };

  DualActiveSet(const BoxQp<T>& qp, T tol_t, T tol_g, T tiny) : qp_(qp), tol_t_(tol_t), tol_g_(tol_g), tiny_(tiny) {}

  // Starts from the given active set (the previous tick's); `max_changes` bounds the active-set changes.
  Outcome run(Mask lower, Mask upper, int max_changes) {
    lower_ = lower;
    upper_ = static_cast<Mask>(upper & ~lower);
    save();
    budget_ = max_changes;
    for (int i = 0; i < kStrings; ++i)
      t_[i] = (lower_ & bit(i)) ? qp_.lo : ((upper_ & bit(i)) ? qp_.hi : static_cast<T>(0));
    // Every pass ends on a fresh Cholesky solve for the active set it reached, and the optimality test is
    // made on that: the swept matrix only steers the search, so the rounding its sweeps collect (sweeping
    // out cancels digits) never reaches the answer. Most ticks the first guess is right and this solve is
    // all there is. A second pass starts a fresh swept matrix from where the first one ended.
    for (;;) {
      if (!solve_held_cholesky()) return Outcome::singular;
      if (optimal_now()) return Outcome::optimal;
      if (changes_ >= budget_) return Outcome::out_of_budget;
      const Outcome o = search();
      if (o != Outcome::optimal) return o;
    }
  }

  const T (&tensions() const)[kStrings] { return t_; }
  // The active set to start the next solve from: after an overrun, the last one reached by a completed
  // step (a release of a wrong-signed string, or a finished push), never one in the middle of a push —
  // a push cut short would be undone by the next solve, and a static scene could then cycle forever.
  Mask lower() const { return saved_lower_; }
  Mask upper() const { return saved_upper_; }
  int changes() const { return changes_; }

 private:
  bool is_active(int i) const { return ((lower_ | upper_) & bit(i)) != 0; }
  void save() {
    saved_lower_ = lower_;
    saved_upper_ = upper_;
  }
  // Oriented so that ≥ 0 means the bound is holding the string where the objective wants it.
  T multiplier(int j) const { return (lower_ & bit(j)) ? grad_[j] : -grad_[j]; }

  bool release(int j) {
    ++changes_;
    lower_ &= static_cast<Mask>(~bit(j));
    upper_ &= static_cast<Mask>(~bit(j));
    return sweep(s_, j, true, tiny_);
  }

  // Goldfarb–Idnani from the current active set (t and the gradients must be the held optimum).
  Outcome search() {
    for (int i = 0; i < kStrings; ++i)
      for (int j = 0; j < kStrings; ++j) s_[i][j] = qp_.h[i][j];
    for (int i = 0; i < kStrings; ++i)
      if (!is_active(i) && !sweep(s_, i, true, tiny_)) return Outcome::singular;
    // A warm start may hold strings whose multiplier is now negative: release them (worst first).
    for (;;) {
      int worst = -1;
      T worst_mu = -tol_g_;
      for (int j = 0; j < kStrings; ++j)
        if (is_active(j) && multiplier(j) < worst_mu) worst_mu = multiplier(j), worst = j;
      if (worst < 0) break;
      if (changes_ >= budget_) return Outcome::out_of_budget;
      if (!release(worst)) return Outcome::singular;
      save();
      // Releasing a string with gradient γ moves the held optimum by −γ·H_F'F'⁻¹ e_j.
      const T gamma = grad_[worst];
      const T(&col)[kStrings] = s_[worst];  // symmetric: row = column
      for (int i = 0; i < kStrings; ++i) {
        if (is_active(i))
          grad_[i] -= col[i] * gamma;
        else
          t_[i] += col[i] * gamma;
      }
      grad_[worst] = 0;
    }
    for (;;) {
      int p = -1;
      T worst = tol_t_;
      for (int i = 0; i < kStrings; ++i) {
        if (is_active(i)) continue;
        const T v = t_[i] < qp_.lo ? qp_.lo - t_[i] : t_[i] - qp_.hi;
        if (v > worst) worst = v, p = i;
      }
      if (p < 0) return Outcome::optimal;
      const Outcome o = push_to_bound(p);
      if (o != Outcome::optimal) return o;
    }
  }

  // Splits the strings into free (fr) and active (ac) index lists and forms the free strings' right-hand
  // side g_F − H_FA t_A. Returns the number of free strings.
  int held_rhs(int (&fr)[kStrings], int (&ac)[kStrings], int& na, T (&rhs)[kStrings]) const {
    int nf = 0;
    na = 0;
    for (int i = 0; i < kStrings; ++i) {
      if (is_active(i))
        ac[na++] = i;
      else
        fr[nf++] = i;
    }
    for (int a = 0; a < nf; ++a) {
      T r = qp_.g[fr[a]];
      for (int b = 0; b < na; ++b) r -= qp_.h[fr[a]][ac[b]] * t_[ac[b]];
      rhs[a] = r;
    }
    return nf;
  }

  // Free strings' optimum with the active ones at their bounds (H_FF t_F = g_F − H_FA t_A) by Cholesky of
  // the gathered free block, and the active strings' gradients Ht − g.
  bool solve_held_cholesky() {
    int fr[kStrings], ac[kStrings], na;
    T rhs[kStrings];
    const int nf = held_rhs(fr, ac, na, rhs);
    T l[kStrings][kStrings];
    for (int a = 0; a < nf; ++a)
      for (int b = 0; b <= a; ++b) l[a][b] = qp_.h[fr[a]][fr[b]];
    if (!cholesky_factor(l, nf, tiny_)) return false;
    cholesky_solve(l, nf, rhs);
    for (int a = 0; a < nf; ++a) {
      t_[fr[a]] = rhs[a];
      grad_[fr[a]] = 0;
    }
    for (int b = 0; b < na; ++b) {
      T gsum = -qp_.g[ac[b]];
      for (int k = 0; k < kStrings; ++k) gsum += qp_.h[ac[b]][k] * t_[k];
      grad_[ac[b]] = gsum;
    }
    return true;
  }
  // KKT test: free strings within their bounds, active strings' multipliers non-negative.
  bool optimal_now() const {
    for (int i = 0; i < kStrings; ++i) {
      if (is_active(i)) {
        if (multiplier(i) < -tol_g_) return false;
      } else if (t_[i] < qp_.lo - tol_t_ || t_[i] > qp_.hi + tol_t_) {
        return false;
      }
    }
    return true;
  }

  // Apply a growing force τ to string p until it reaches its violated bound. The free strings move along
  // z = H_FF⁻¹ e_p = −s_Fp; active string j's gradient changes at rate s_jp; p's own gradient is the force.
  Outcome push_to_bound(int p) {
    const bool up = t_[p] < qp_.lo;
    const T target = up ? qp_.lo : qp_.hi;
    const T dir = up ? static_cast<T>(1) : static_cast<T>(-1);
    for (;;) {
      if (changes_ >= budget_) return Outcome::out_of_budget;
      const T(&col)[kStrings] = s_[p];
      const T zp = -col[p];
      if (!(zp > 0)) return Outcome::singular;
      T step = (target - t_[p]) * dir / zp;
      int blocking = -1;
      for (int j = 0; j < kStrings; ++j) {
        if (!is_active(j)) continue;
        const T rate = ((lower_ & bit(j)) ? dir : -dir) * col[j];  // d multiplier_j / dτ
        if (rate >= 0) continue;
        const T mu = multiplier(j);
        const T reach = mu > 0 ? mu / -rate : static_cast<T>(0);
        if (reach < step) step = reach, blocking = j;
      }
      const T move = step * dir;
      for (int i = 0; i < kStrings; ++i) {
        if (is_active(i))
          grad_[i] += move * col[i];
        else
          t_[i] -= move * col[i];
      }
      grad_[p] += move;
      if (blocking < 0) {
        t_[p] = target;
        ++changes_;
        (up ? lower_ : upper_) |= bit(p);
        save();
        return sweep(s_, p, false, tiny_) ? Outcome::optimal : Outcome::singular;
      }
      if (!release(blocking)) return Outcome::singular;
      grad_[blocking] = 0;
    }
  }

  const BoxQp<T>& qp_;
  T tol_t_, tol_g_, tiny_;
  T s_[kStrings][kStrings];
  T t_[kStrings];
  T grad_[kStrings];
  Mask lower_ = 0, upper_ = 0, saved_lower_ = 0, saved_upper_ = 0;
  int budget_ = 0, changes_ = 0;
};

// Projected Gauss–Seidel: exact minimisation along each coordinate, clamped to the box. Monotone, so it
// can only improve on its start; polishes the answer when the active-set search runs out of budget.
template <class T>
void projected_gauss_seidel(const BoxQp<T>& qp, T (&t)[kStrings], int sweeps) {
  T inv_diag[kStrings];
  for (int i = 0; i < kStrings; ++i) inv_diag[i] = qp.h[i][i] > 0 ? static_cast<T>(1) / qp.h[i][i] : 0;
  for (int s = 0; s < sweeps; ++s)
    for (int i = 0; i < kStrings; ++i) {
      if (!(qp.h[i][i] > 0)) continue;
      const T step = -gradient(qp, t, i) * inv_diag[i];
      t[i] = clamp_to(t[i] + step, qp.lo, qp.hi);
    }
}

template <class T>
void finish(const StringGeometry<T>& strings, TensionResult<T>& r, T lo, T hi) {
  r.force = {};
  r.torque = {};
  for (int i = 0; i < kStrings; ++i) {
    r.tension[i] = clamp_to(r.tension[i], lo, hi);
    r.force += r.tension[i] * strings.u[i];
    r.torque += r.tension[i] * strings.m[i];
  }
}

}  // namespace

template <class T>
TensionResult<T> solve_tensions(const StringGeometry<T>& strings, const Vec3<T>& force, const Vec3<T>& torque,
                                const TensionParams<T>& params, TensionState& state) {
  TensionResult<T> r;
  r.flags = strings.flags;
  // The bounds themselves are made safe first: whatever else fails, the answer lies in [lo, hi].
  const T lo = std::isfinite(params.t_min) && params.t_min >= 0 ? params.t_min : static_cast<T>(0);
  const T hi = std::isfinite(params.t_max) && params.t_max >= lo ? params.t_max : lo;
  for (T& t : r.tension) t = lo;

  BoxQp<T> qp;
  qp.lo = lo;
  qp.hi = hi;
  const bool usable = !(strings.flags & flag::invalid_input) && params.lambda_t >= 0 && params.lambda_r >= 0 &&
                      params.regulariser >= 0 && params.t_min == lo && params.t_max == hi;
  if (!usable || !build_qp(strings, force, torque, params, qp)) {
    r.flags |= flag::invalid_input;
    state = {};
    finish(strings, r, lo, hi);
    if (!is_finite(r.force) || !is_finite(r.torque)) r.force = r.torque = {};  // unknown, not NaN
    return r;
  }
  r.flags |= conditioning_flags(strings, params.degenerate_ratio);

  // Tolerances for the optimality test: a few ulps of the quantities compared.
  constexpr T eps = std::numeric_limits<T>::epsilon();
  T h_max = 0, g_max = 0;
  for (int i = 0; i < kStrings; ++i) {
    h_max = qp.h[i][i] > h_max ? qp.h[i][i] : h_max;
    g_max = std::fabs(qp.g[i]) > g_max ? std::fabs(qp.g[i]) : g_max;
  }
  const T tol_t = static_cast<T>(16) * eps * (hi > 1 ? hi : static_cast<T>(1));
  const T tol_g = static_cast<T>(16) * eps * (g_max + h_max * hi);
  const T tiny = static_cast<T>(64) * eps * h_max;

  DualActiveSet<T> solver(qp, tol_t, tol_g, tiny);
  const auto outcome = solver.run(state.at_lower, state.at_upper, params.max_iterations);
  r.iterations = static_cast<std::uint8_t>(solver.changes());
  for (int i = 0; i < kStrings; ++i) r.tension[i] = solver.tensions()[i];
  Mask lower = solver.lower(), upper = solver.upper();
  if (outcome != DualActiveSet<T>::Outcome::optimal) {
    r.flags |= outcome == DualActiveSet<T>::Outcome::singular ? flag::ill_conditioned : flag::not_converged;
    // The dual method's iterates break bounds until it finishes: clamp, then polish monotonically.
    finish(strings, r, lo, hi);
    projected_gauss_seidel(qp, r.tension, params.fallback_sweeps);
    // Out of budget: keep the active set reached so far, the next tick carries on from it. Singular: the
    // set is suspect, start the next tick from scratch.
    if (outcome == DualActiveSet<T>::Outcome::singular) lower = upper = 0;
  }
  state.at_lower = lower;
  state.at_upper = upper;
  finish(strings, r, lo, hi);
  return r;
}

template TensionResult<float> solve_tensions<float>(const StringGeometry<float>&, const Vec3<float>&,
                                                    const Vec3<float>&, const TensionParams<float>&, TensionState&);
template TensionResult<double> solve_tensions<double>(const StringGeometry<double>&, const Vec3<double>&,
                                                      const Vec3<double>&, const TensionParams<double>&, TensionState&);

}  // namespace hmp::spidar
