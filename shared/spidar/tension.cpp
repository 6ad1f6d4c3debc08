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

template <class T> T clamp_to(T v, T lo, T hi) { return v >= lo ? (v <= hi ? v : hi) : lo; }  // NaN → lo

// H = λt UᵀU + λr MᵀM + s I and g = λt UᵀF + λr MᵀN, with √λ folded into the vectors so each entry is one
// 6-term dot product. Returns false if anything came out non-finite.
template <class T>
bool build_qp(const StringGeometry<T>& strings, const Vec3<T>& force, const Vec3<T>& torque,
              const TensionParams<T>& p, BoxQp<T>& qp) {
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

template <class T> T gradient(const BoxQp<T>& qp, const T (&t)[kStrings], int i) {
  T s = -qp.g[i];
  for (int j = 0; j < kStrings; ++j) s += qp.h[i][j] * t[j];
  return s;
}

// Free strings' tensions for the given active set (active ones already at their bounds in t).
template <class T>
bool solve_free(const BoxQp<T>& qp, Mask active, T (&t)[kStrings], T tiny) {
  int idx[kStrings];
  int n = 0;
  for (int i = 0; i < kStrings; ++i)
    if (!(active & bit(i))) idx[n++] = i;
  T a[kStrings][kStrings];
  T rhs[kStrings];
  for (int r = 0; r < n; ++r) {
    const int i = idx[r];
    T s = qp.g[i];
    for (int j = 0; j < kStrings; ++j)
      if (active & bit(j)) s -= qp.h[i][j] * t[j];
    rhs[r] = s;
    for (int c = 0; c <= r; ++c) a[r][c] = qp.h[i][idx[c]];
  }
  if (!cholesky_solve(a, n, rhs, tiny)) return false;
  for (int r = 0; r < n; ++r) t[idx[r]] = rhs[r];
  return true;
}

// Projected Gauss–Seidel: exact minimisation along each coordinate, clamped to the box. Monotone, so it
// can only improve on its start; used when block pivoting runs out of iterations.
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

  // Block principal pivoting (Júdice & Pires): exchange every infeasible string while their number keeps
  // falling (with a few grace steps), otherwise exchange only the highest-numbered one (Murty's rule), which
  // cannot cycle for a positive definite H.
  Mask lower = state.at_lower;
  Mask upper = static_cast<Mask>(state.at_upper & ~lower);
  T t[kStrings];
  for (T& v : t) v = lo;
  int best = kStrings + 1, grace = 3;
  bool converged = false, solved = false;
  int it = 0;
  while (it < params.max_iterations) {
    for (int i = 0; i < kStrings; ++i) t[i] = (lower & bit(i)) ? lo : ((upper & bit(i)) ? hi : t[i]);
    ++it;
    if (!solve_free(qp, static_cast<Mask>(lower | upper), t, tiny)) {
      r.flags |= flag::ill_conditioned;
      break;
    }
    solved = true;
    Mask to_lower = 0, to_upper = 0, to_free = 0;
    for (int i = 0; i < kStrings; ++i) {
      if (lower & bit(i)) {
        if (gradient(qp, t, i) < -tol_g) to_free |= bit(i);  // pulling it above t_min lowers the cost
      } else if (upper & bit(i)) {
        if (gradient(qp, t, i) > tol_g) to_free |= bit(i);
      } else if (t[i] < lo - tol_t) {
        to_lower |= bit(i);
      } else if (t[i] > hi + tol_t) {
        to_upper |= bit(i);
      }
    }
    Mask wrong = static_cast<Mask>(to_lower | to_upper | to_free);
    if (!wrong) {
      converged = true;
      break;
    }
    int count = 0;
    for (int i = 0; i < kStrings; ++i) count += (wrong >> i) & 1;
    if (count < best) {
      best = count;
      grace = 3;
    } else if (grace > 0) {
      --grace;
    } else {
      Mask top = 0x80;
      while (!(wrong & top)) top = static_cast<Mask>(top >> 1);
      to_lower &= top;
      to_upper &= top;
      to_free &= top;
    }
    lower = static_cast<Mask>((lower & ~to_free) | to_lower);
    upper = static_cast<Mask>((upper & ~to_free) | to_upper);
  }
  r.iterations = static_cast<std::uint8_t>(it);

  if (solved) {
    for (int i = 0; i < kStrings; ++i) r.tension[i] = t[i];
  }
  if (!converged) {
    r.flags |= flag::not_converged;
    finish(strings, r, lo, hi);  // clamp the last iterate, then polish it monotonically
    projected_gauss_seidel(qp, r.tension, params.fallback_sweeps);
    lower = upper = 0;
    for (int i = 0; i < kStrings; ++i) {
      if (r.tension[i] <= lo) lower |= bit(i);
      else if (r.tension[i] >= hi) upper |= bit(i);
    }
  }
  state.at_lower = lower;
  state.at_upper = upper;
  finish(strings, r, lo, hi);
  return r;
}

template TensionResult<float> solve_tensions<float>(const StringGeometry<float>&, const Vec3<float>&,
                                                    const Vec3<float>&, const TensionParams<float>&, TensionState&);
template TensionResult<double> solve_tensions<double>(const StringGeometry<double>&, const Vec3<double>&,
                                                      const Vec3<double>&, const TensionParams<double>&,
                                                      TensionState&);

}  // namespace hmp::spidar
