// The SPIDAR tension QP (shared/spidar/tension) against an independent brute-force solver: every one of the
// 3^8 active sets (each string at t_min, at t_max or free), the free subsystem solved by Gaussian
// elimination, KKT-feasible candidates kept, the smallest objective taken. Plus bounds, flags and
// degenerate geometry.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "shared/spidar/geometry.hpp"
#include "shared/spidar/tension.hpp"
#include "tests/sim/spidar_reference.hpp"

namespace {

using namespace hmp::spidar;
using spidar_ref::V3;

struct Weights {
  double t_min, t_max, lt, lr, s;
};
Weights weights_of(const TensionParams<double>& p) {
  return {p.t_min, p.t_max, p.lambda_t, p.lambda_r, p.regulariser};
}

// λt|F − Σ t u|² + λr|N − Σ t m|² + s|t|², straight from SPEC §11.
double objective(const spidar_ref::Strings& st, const V3& f, const V3& n, const Weights& w, const double* t) {
  V3 ef = f, en = n;
  double tt = 0;
  for (int i = 0; i < 8; ++i) {
    ef = spidar_ref::sub(ef, spidar_ref::scale(t[i], st.u[i]));
    en = spidar_ref::sub(en, spidar_ref::scale(t[i], st.m[i]));
    tt += t[i] * t[i];
  }
  return w.lt * spidar_ref::dot3(ef, ef) + w.lr * spidar_ref::dot3(en, en) + w.s * tt;
}

struct Reference {
  double t[8];
  double objective;
  int candidates;  // KKT points found (1 for a strictly convex problem)
};

// Brute force over all 3^8 active sets.
Reference enumerate(const spidar_ref::Strings& st, const V3& f, const V3& n, const Weights& w) {
  double h[8][8], g[8];  // ½ tᵀHt − gᵀt
  for (int i = 0; i < 8; ++i) {
    g[i] = w.lt * spidar_ref::dot3(st.u[i], f) + w.lr * spidar_ref::dot3(st.m[i], n);
    for (int j = 0; j < 8; ++j)
      h[i][j] = w.lt * spidar_ref::dot3(st.u[i], st.u[j]) + w.lr * spidar_ref::dot3(st.m[i], st.m[j]) + (i == j ? w.s : 0);
  }
  const double tol = 1e-9 * (1 + w.t_max);
  Reference best{};
  best.objective = std::numeric_limits<double>::infinity();
  for (int code = 0; code < 6561; ++code) {
    int state[8], free_idx[8], nf = 0;
    double t[8];
    for (int i = 0, c = code; i < 8; ++i, c /= 3) {
      state[i] = c % 3;
      t[i] = state[i] == 1 ? w.t_min : (state[i] == 2 ? w.t_max : 0);
      if (state[i] == 0) free_idx[nf++] = i;
    }
    double a[8][9];  // augmented system of the free tensions
    for (int r = 0; r < nf; ++r) {
      double rhs = g[free_idx[r]];
      for (int j = 0; j < 8; ++j)
        if (state[j]) rhs -= h[free_idx[r]][j] * t[j];
      for (int c = 0; c < nf; ++c) a[r][c] = h[free_idx[r]][free_idx[c]];
      a[r][nf] = rhs;
    }
    bool singular = false;
    for (int k = 0; k < nf && !singular; ++k) {
      int p = k;
      for (int r = k + 1; r < nf; ++r)
        if (std::fabs(a[r][k]) > std::fabs(a[p][k])) p = r;
      if (std::fabs(a[p][k]) < 1e-300) { singular = true; break; }
      for (int c = 0; c <= nf; ++c) std::swap(a[k][c], a[p][c]);
      for (int r = k + 1; r < nf; ++r) {
        const double factor = a[r][k] / a[k][k];
        for (int c = k; c <= nf; ++c) a[r][c] -= factor * a[k][c];
      }
    }
    if (singular) continue;
    bool feasible = true;
    for (int r = nf - 1; r >= 0; --r) {
      double s = a[r][nf];
      for (int c = r + 1; c < nf; ++c) s -= a[r][c] * t[free_idx[c]];
      t[free_idx[r]] = s / a[r][r];
      if (t[free_idx[r]] < w.t_min - tol || t[free_idx[r]] > w.t_max + tol) { feasible = false; break; }
    }
    if (!feasible) continue;
    for (int i = 0; i < 8 && feasible; ++i) {
      if (!state[i]) continue;
      double grad = -g[i];
      for (int j = 0; j < 8; ++j) grad += h[i][j] * t[j];
      if ((state[i] == 1 && grad < -tol) || (state[i] == 2 && grad > tol)) feasible = false;
    }
    if (!feasible) continue;
    ++best.candidates;
    const double obj = objective(st, f, n, w, t);
    if (obj < best.objective) {
      best.objective = obj;
      std::copy(t, t + 8, best.t);
    }
  }
  return best;
}

template <class T> Vec3<T> vec(const V3& v) {
  return {static_cast<T>(v[0]), static_cast<T>(v[1]), static_cast<T>(v[2])};
}
template <class T> Pose<T> pose_of(const spidar_ref::RandomPose& p) {
  const double c = std::cos(p.angle / 2), s = std::sin(p.angle / 2);
  return {vec<T>(p.pos), Quat<T>{static_cast<T>(c), static_cast<T>(s * p.axis[0]), static_cast<T>(s * p.axis[1]),
                                 static_cast<T>(s * p.axis[2])}};
}
template <class T> TensionParams<T> params_as(const TensionParams<double>& d) {
  TensionParams<T> p;
  p.t_min = static_cast<T>(d.t_min);
  p.t_max = static_cast<T>(d.t_max);
  p.lambda_t = static_cast<T>(d.lambda_t);
  p.lambda_r = static_cast<T>(d.lambda_r);
  p.regulariser = static_cast<T>(d.regulariser);
  p.max_iterations = d.max_iterations;
  return p;
}

void record(const char* key, double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3e", value);
  ::testing::Test::RecordProperty(key, text);
  std::printf("  %-34s %s\n", key, text);
}

bool within(double t, double lo, double hi) { return std::isfinite(t) && t >= lo && t <= hi; }

TEST(SpidarGeometry, X3TableMatchesSpec) {
  const Frame<double> frame = x3_frame<double>();
  const spidar_ref::Device ref = spidar_ref::x3_device();
  for (int i = 0; i < 8; ++i) {
    EXPECT_NEAR(frame.motor_exit[i].x, ref.motor[i][0], 1e-15) << i;
    EXPECT_NEAR(frame.motor_exit[i].y, ref.motor[i][1], 1e-15) << i;
    EXPECT_NEAR(frame.motor_exit[i].z, ref.motor[i][2], 1e-15) << i;
    EXPECT_NEAR(frame.attachment[i].x, ref.attach[i][0], 1e-15) << i;
    EXPECT_NEAR(frame.attachment[i].y, ref.attach[i][1], 1e-15) << i;
    EXPECT_NEAR(frame.attachment[i].z, ref.attach[i][2], 1e-15) << i;
  }
  // Turned −45° about y: corner (−,·,+) lands on the −x axis, (+,·,+) on +z.
  EXPECT_NEAR(frame.motor_exit[0].x, -0.06 * std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(frame.motor_exit[0].z, 0.0, 1e-15);
  EXPECT_NEAR(frame.motor_exit[1].z, 0.06 * std::sqrt(2.0), 1e-15);
}

TEST(SpidarGeometry, StringsMatchReference) {
  const Frame<double> frame = x3_frame<double>();
  const spidar_ref::Device dev = spidar_ref::x3_device();
  std::mt19937_64 rng(11);
  for (int k = 0; k < 1000; ++k) {
    const spidar_ref::RandomPose p = spidar_ref::random_pose(rng, 1.0, 0.5);
    const spidar_ref::Strings ref = spidar_ref::strings_at(dev, p.pos, p.rot);
    StringGeometry<double> s;
    compute_strings(frame, pose_of<double>(p), s);
    EXPECT_EQ(s.flags, 0);
    for (int i = 0; i < 8; ++i) {
      ASSERT_NEAR(s.length[i], ref.length[i], 1e-14);
      for (int c = 0; c < 3; ++c) {
        ASSERT_NEAR((&s.u[i].x)[c], ref.u[i][c], 1e-13);
        ASSERT_NEAR((&s.m[i].x)[c], ref.m[i][c], 1e-14);
      }
    }
    EXPECT_EQ(conditioning_flags(s, 1e-3), 0) << "workspace pose flagged degenerate";
  }
}

// The main agreement test: 10,000 random poses × wrenches, cold-started (the hardest case for the active set).
TEST(SpidarQp, MatchesBruteForceOnRandomProblems) {
  const Frame<double> frame_d = x3_frame<double>();
  const Frame<float> frame_f = x3_frame<float>();
  const spidar_ref::Device dev = spidar_ref::x3_device();
  const TensionParams<double> pd;
  const TensionParams<float> pf = params_as<float>(pd);
  const Weights w = weights_of(pd);
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> unit(-1, 1);

  double worst_rel_d = 0, worst_rel_f = 0, worst_force_f = 0, worst_t_f = 0;
  int max_it_d = 0, max_it_f = 0, sum_it_d = 0, multi_kkt = 0;
  constexpr int kCases = 10000;
  for (int k = 0; k < kCases; ++k) {
    const spidar_ref::RandomPose p = spidar_ref::random_pose(rng, 0.95, 0.35);
    const V3 f{10 * unit(rng), 10 * unit(rng), 10 * unit(rng)};
    const V3 n{0.05 * unit(rng), 0.05 * unit(rng), 0.05 * unit(rng)};
    const spidar_ref::Strings ref_strings = spidar_ref::strings_at(dev, p.pos, p.rot);
    const Reference ref = enumerate(ref_strings, f, n, w);
    ASSERT_GE(ref.candidates, 1) << k;
    multi_kkt += ref.candidates > 1;

    StringGeometry<double> sd;
    compute_strings(frame_d, pose_of<double>(p), sd);
    TensionState state_d;
    const TensionResult<double> rd = solve_tensions(sd, vec<double>(f), vec<double>(n), pd, state_d);
    ASSERT_EQ(rd.flags, 0) << k;
    for (int i = 0; i < 8; ++i) ASSERT_TRUE(within(rd.tension[i], pd.t_min, pd.t_max)) << k;
    const double obj_d = objective(ref_strings, f, n, w, rd.tension);
    const double rel_d = std::fabs(obj_d - ref.objective) / ref.objective;
    ASSERT_LE(rel_d, 1e-6) << "case " << k;
    worst_rel_d = std::max(worst_rel_d, rel_d);
    max_it_d = std::max<int>(max_it_d, rd.iterations);
    sum_it_d += rd.iterations;
    // The achieved wrench is Σ t u, Σ t m of the returned tensions.
    V3 force{}, torque{};
    for (int i = 0; i < 8; ++i) {
      force = spidar_ref::add(force, spidar_ref::scale(rd.tension[i], ref_strings.u[i]));
      torque = spidar_ref::add(torque, spidar_ref::scale(rd.tension[i], ref_strings.m[i]));
    }
    ASSERT_NEAR(rd.force.x, force[0], 1e-12);
    ASSERT_NEAR(rd.force.y, force[1], 1e-12);
    ASSERT_NEAR(rd.torque.z, torque[2], 1e-12);

    // The firmware's float path on the same problem, judged by the double objective.
    StringGeometry<float> sf;
    compute_strings(frame_f, pose_of<float>(p), sf);
    TensionState state_f;
    const TensionResult<float> rf = solve_tensions(sf, vec<float>(f), vec<float>(n), pf, state_f);
    double tf[8];
    V3 force_f{};
    for (int i = 0; i < 8; ++i) {
      ASSERT_TRUE(within(rf.tension[i], pf.t_min, pf.t_max)) << k;
      tf[i] = static_cast<double>(rf.tension[i]);
      force_f = spidar_ref::add(force_f, spidar_ref::scale(tf[i], ref_strings.u[i]));
      worst_t_f = std::max(worst_t_f, std::fabs(tf[i] - ref.t[i]));
    }
    EXPECT_FALSE(rf.flags & flag::not_converged) << k;
    worst_rel_f = std::max(worst_rel_f, (objective(ref_strings, f, n, w, tf) - ref.objective) / ref.objective);
    worst_force_f = std::max(worst_force_f, spidar_ref::len3(spidar_ref::sub(force_f, force)));
    max_it_f = std::max<int>(max_it_f, rf.iterations);
  }
  std::printf("QP vs brute force, %d cold-started cases:\n", kCases);
  record("double_max_rel_objective_error", worst_rel_d);
  record("double_mean_iterations", static_cast<double>(sum_it_d) / kCases);
  record("double_max_iterations", max_it_d);
  record("float_max_rel_objective_excess", worst_rel_f);
  record("float_max_force_deviation_N", worst_force_f);
  record("float_max_tension_deviation_N", worst_t_f);
  record("float_max_iterations", max_it_f);
  record("cases_with_several_kkt_points", multi_kkt);
  EXPECT_LE(max_it_f, pf.max_iterations);
  EXPECT_LE(worst_rel_f, 1e-4);
  EXPECT_LE(worst_force_f, 1e-3);
}

}  // namespace
