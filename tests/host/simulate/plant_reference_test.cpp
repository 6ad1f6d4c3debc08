// host/simulate: the CVODE reference of the plant simulator, checked against what is known independently —
// the plant's own RK4 at tiny steps where the right-hand side is smooth, the exact solution of the plant
// linearised at its stiffest strings, its own convergence in a scene whose strings go slack and taut, the
// one-tick reference from a run's states, and the plant's handling of bad duties.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "boards/sim/plant/dynamics.hpp"
#include "boards/sim/plant/plant.hpp"
#include "host/simulate/plant_reference.hpp"

namespace {

namespace plant = hmp::sim::plant;
using hmp::simulate::PlantDrive;
using hmp::simulate::PlantTrace;
using hmp::simulate::ReferenceOptions;
using Duties = std::array<double, 8>;

constexpr double kBias = 0.3;   // N
constexpr double kTick = 1e-3;  // s

// Every motor at the duty that holds the bias tension at standstill; motors 0 and 1 swing by ±`swing` at
// 250 Hz on top. `duty(k, i)` may override.
PlantDrive holding_drive(const plant::PlantParams& params, int ticks, double swing) {
  const plant::Plant p(params);
  const double hold = p.holding_duty(kBias);
  PlantDrive drive;
  drive.tick_s = kTick;
  for (int k = 0; k < ticks; ++k) {
    Duties d;
    d.fill(hold);
    const double s = swing * std::sin(2 * M_PI * 250.0 * k * kTick);
    d[0] += s;
    d[1] += s;
    drive.duty.push_back(d);
    drive.anchor.push_back(params.finger.anchor);
  }
  return drive;
}

// holding_drive() with motors 0–3 let go (duty 0) over ticks [from, to): their strings go slack and then
// snap taut.
PlantDrive releasing_drive(const plant::PlantParams& params, int ticks, double swing, int from, int to) {
  PlantDrive drive = holding_drive(params, ticks, swing);
  for (int k = from; k < to; ++k)
    for (int i = 0; i < 4; ++i) drive.duty[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)] = 0.0;
  return drive;
}

// The plant's own stepping, tick by tick, with the same drive.
std::vector<plant::Vec3d> plant_string_force(const plant::PlantParams& params, const PlantDrive& drive) {
  plant::Plant p(params);
  p.reset(kBias);
  std::vector<plant::Vec3d> out;
  for (std::size_t k = 0; k < drive.duty.size(); ++k) {
    double d[8];
    for (int i = 0; i < 8; ++i) d[i] = drive.duty[k][static_cast<std::size_t>(i)];
    p.set_finger_anchor(drive.anchor[k]);
    out.push_back(p.step(d, drive.tick_s).string_force);
  }
  return out;
}

// RMS of |a − b| over the RMS of b's variation about its mean: 0 for identical traces, 1 for a trace that
// misses the whole signal.
double relative_rms(const std::vector<plant::Vec3d>& a, const std::vector<plant::Vec3d>& b) {
  if (a.size() != b.size() || b.empty()) return std::numeric_limits<double>::infinity();
  plant::Vec3d mean{};
  for (const plant::Vec3d& v : b) mean += v;
  mean = (1.0 / static_cast<double>(b.size())) * mean;
  double err = 0, signal = 0;
  for (std::size_t k = 0; k < b.size(); ++k) {
    const plant::Vec3d d = a[k] - b[k], s = b[k] - mean;
    err += dot(d, d);
    signal += dot(s, s);
  }
  return std::sqrt(err / signal);
}

void print(const char* what, const hmp::simulate::SolverStats& s) {
  std::printf("[ reference ] %s: %ld steps, %ld rhs evaluations, %ld roots, %.3f s CPU\n", what, s.steps, s.rhs_evals,
              s.roots, s.cpu_s);
}

TEST(PlantReference, AgreesWithFineRk4InTheNominalScene) {
  plant::PlantParams params;
  const PlantDrive drive = holding_drive(params, 200, 0.02);
  const PlantTrace ref = hmp::simulate::cvode_reference(params, kBias, drive);
  ASSERT_TRUE(ref.ok) << ref.error;
  print("nominal, 0.2 s", ref);
  ASSERT_EQ(ref.string_force.size(), drive.duty.size());
  EXPECT_EQ(ref.tension.size(), drive.duty.size());
  EXPECT_EQ(ref.finger_force.size(), drive.duty.size());

  params.stepper.method = plant::Method::rk4;
  params.stepper.max_step = 1e-3 / 512;
  const std::vector<plant::Vec3d> rk4 = plant_string_force(params, drive);
  const double error = relative_rms(ref.string_force, rk4);
  std::printf("[ reference ] nominal: string force relative RMS error against RK4 %.3g\n", error);
  EXPECT_LT(error, 1e-6);
}

// ---- the plant linearised at stiffness 10⁷ N/m: its exact solution through a matrix exponential ----------

using Matrix = std::vector<std::vector<long double>>;

Matrix multiply(const Matrix& a, const Matrix& b) {
  const std::size_t n = a.size();
  Matrix c(n, std::vector<long double>(n, 0.0L));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < n; ++k) {
      const long double aik = a[i][k];
      if (aik == 0) continue;
      for (std::size_t j = 0; j < n; ++j) c[i][j] += aik * b[k][j];
    }
  return c;
}

long double norm1(const Matrix& a) {
  long double best = 0;
  for (std::size_t j = 0; j < a.size(); ++j) {
    long double col = 0;
    for (std::size_t i = 0; i < a.size(); ++i) col += std::fabs(a[i][j]);
    best = std::max(best, col);
  }
  return best;
}

// e^M: balanced by a diagonal similarity (powers of two, Parlett–Reinsch: the plant's states mix units of
// very different sizes), then scaled by 2^-s to a norm below ½, a Taylor series to long double precision,
// and s squarings.
Matrix expm(Matrix m) {
  const std::size_t n = m.size();
  std::vector<long double> d(n, 1.0L);
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t i = 0; i < n; ++i) {
      long double row = 0, col = 0;
      for (std::size_t j = 0; j < n; ++j)
        if (j != i) {
          row += std::fabs(m[i][j]);
          col += std::fabs(m[j][i]);
        }
      if (row == 0 || col == 0) continue;
      long double f = 1;
      const long double sum = row + col;
      while (col < row / 2) {
        col *= 2;
        row /= 2;
        f *= 2;
      }
      while (col >= row * 2) {
        col /= 2;
        row *= 2;
        f /= 2;
      }
      if (row + col < 0.95L * sum) {
        changed = true;
        d[i] *= f;
        for (std::size_t j = 0; j < n; ++j) {
          m[i][j] /= f;
          m[j][i] *= f;
        }
      }
    }
  }
  int s = 0;
  const long double norm = norm1(m);
  while (std::ldexp(norm, -s) > 0.5L) ++s;
  for (auto& row : m)
    for (long double& v : row) v = std::ldexp(v, -s);
  Matrix sum(n, std::vector<long double>(n, 0.0L)), term = sum;
  for (std::size_t i = 0; i < n; ++i) sum[i][i] = term[i][i] = 1;
  for (int k = 1; k < 40; ++k) {
    term = multiply(term, m);
    for (auto& row : term)
      for (long double& v : row) v /= k;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j) sum[i][j] += term[i][j];
    if (norm1(term) < 1e-22L) break;
  }
  for (int k = 0; k < s; ++k) sum = multiply(sum, sum);
  for (std::size_t i = 0; i < n; ++i)  // undo the balancing: e^M = D·e^(D⁻¹MD)·D⁻¹
    for (std::size_t j = 0; j < n; ++j) sum[i][j] *= d[i] / d[j];
  return sum;
}

TEST(PlantReference, MatchesTheExactSolutionOfTheLinearisedStiffPlant) {
  plant::PlantParams params;
  params.string.stiffness = 1e7;
  params.scene.translation_only = true;
  plant::Plant p(params);
  p.reset(kBias);
  plant::PlantDynamics dynamics = p.dynamics();
  const int n = dynamics.size();
  ASSERT_EQ(n, plant::state::translation_size);
  const std::vector<double> y0(p.state(), p.state() + n);
  const double supply = params.motor.drive.supply_voltage, inductance = params.motor.inductance;
  double v0[8];
  for (int i = 0; i < 8; ++i) v0[i] = p.holding_duty(kBias) * supply;  // the reset's voltages (stall equation)
  for (int i = 0; i < 8; ++i) dynamics.set_voltage(i, v0[i]);

  // z = y − y0:  z' = A z + f(y0) + ΔV/L on the currents.
  std::vector<double> f0(static_cast<std::size_t>(n));
  dynamics.smooth_derivative(y0.data(), f0.data());
  std::vector<std::vector<double>> a(static_cast<std::size_t>(n), std::vector<double>(static_cast<std::size_t>(n)));
  for (int j = 0; j < n; ++j) {
    const double h = 1e-6 * dynamics.scale(j);
    std::vector<double> up = y0, down = y0, fu(f0.size()), fd(f0.size());
    up[static_cast<std::size_t>(j)] += h;
    down[static_cast<std::size_t>(j)] -= h;
    dynamics.smooth_derivative(up.data(), fu.data());
    dynamics.smooth_derivative(down.data(), fd.data());
    for (int i = 0; i < n; ++i)
      a[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] =
          (fu[static_cast<std::size_t>(i)] - fd[static_cast<std::size_t>(i)]) / (2 * h);
  }

  const int ticks = 50;
  const PlantDrive drive = holding_drive(params, ticks, 0.02);
  auto delta_v = [&](int k, int i) {
    return drive.duty[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)] * supply - v0[i];
  };

  // Exact: with inputs u = (1, ΔV_0..ΔV_7) held over a tick, e^([[A, B], [0, 0]]·h) = [[Φ, Γ], [0, I]] and
  // z_{k+1} = Φ z_k + Γ u_k.
  const int m = n + 9;
  Matrix aug(static_cast<std::size_t>(m), std::vector<long double>(static_cast<std::size_t>(m), 0.0L));
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) aug[i][j] = static_cast<long double>(a[i][j]) * static_cast<long double>(kTick);
    aug[i][n] = static_cast<long double>(f0[static_cast<std::size_t>(i)]) * static_cast<long double>(kTick);
  }
  for (int i = 0; i < 8; ++i)
    aug[plant::state::current + i][n + 1 + i] = static_cast<long double>(kTick) / static_cast<long double>(inductance);
  const Matrix phi = expm(aug);
  std::vector<std::vector<double>> exact;
  std::vector<long double> z(static_cast<std::size_t>(n), 0.0L);
  for (int k = 0; k < ticks; ++k) {
    std::vector<long double> u(9, 1.0L), next(z.size(), 0.0L);
    for (int i = 0; i < 8; ++i) u[static_cast<std::size_t>(1 + i)] = static_cast<long double>(delta_v(k, i));
    for (int i = 0; i < n; ++i) {
      long double acc = 0;
      for (int j = 0; j < n; ++j) acc += phi[i][j] * z[static_cast<std::size_t>(j)];
      for (int j = 0; j < 9; ++j) acc += phi[i][n + j] * u[static_cast<std::size_t>(j)];
      next[static_cast<std::size_t>(i)] = acc;
    }
    z = next;
    exact.emplace_back(z.begin(), z.end());
  }

  // The same linear system through CVODE. Per block of states (angles, speeds, currents, position,
  // velocity): the largest deviation from the exact solution over the largest excursion of it.
  const int blocks[] = {plant::state::angle,    plant::state::speed,    plant::state::current,
                        plant::state::position, plant::state::velocity, n};
  constexpr int kBlocks = static_cast<int>(std::size(blocks)) - 1;
  auto solve = [&](const ReferenceOptions& options, std::array<double, kBlocks>& relative) {
    hmp::simulate::SwitchedOde ode;
    ode.size = n;
    for (int i = 0; i < n; ++i) ode.atol.push_back(options.atol_factor * dynamics.scale(i));
    int tick = 0;
    ode.begin_tick = [&](int k) { tick = k; };
    ode.rhs = [&](const double* y, double* dydt) {
      for (int i = 0; i < n; ++i) {
        double acc = f0[static_cast<std::size_t>(i)];
        for (int j = 0; j < n; ++j) acc += a[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] * y[j];
        dydt[i] = acc;
      }
      for (int i = 0; i < 8; ++i) dydt[plant::state::current + i] += delta_v(tick, i) / inductance;
    };
    std::vector<std::vector<double>> solved;
    std::vector<double> y(static_cast<std::size_t>(n), 0.0);
    const hmp::simulate::SolverStats stats = hmp::simulate::cvode_integrate(
        ode, y, ticks, kTick, options.rtol, [&](int, const double* s) { solved.emplace_back(s, s + n); });
    if (!stats.ok || solved.size() != exact.size()) return stats;
    for (int b = 0; b < kBlocks; ++b) {
      double error = 0, excursion = 0;
      for (int k = 0; k < ticks; ++k) {
        double e2 = 0, x2 = 0;
        for (int i = blocks[b]; i < blocks[b + 1]; ++i) {
          const double d = solved[k][i] - exact[k][i];
          e2 += d * d;
          x2 += exact[k][i] * exact[k][i];
        }
        error = std::max(error, std::sqrt(e2));
        excursion = std::max(excursion, std::sqrt(x2));
      }
      relative[static_cast<std::size_t>(b)] = excursion > 0 ? error / excursion : 1.0;
      std::printf("[ reference ] linearised, rtol %g: block at state %2d: excursion %.3g, relative error %.3g\n",
                  options.rtol, blocks[b], excursion, relative[static_cast<std::size_t>(b)]);
    }
    return stats;
  };

  // At the reference's tolerances, the stretches (angles, position) to 1e-8; the rates, which carry the
  // strings' lightly damped ~7 kHz vibration through 350 periods, only to ~2e-7 (measured).
  std::array<double, kBlocks> coarse{}, fine{};
  const hmp::simulate::SolverStats stats = solve(ReferenceOptions{}, coarse);
  ASSERT_TRUE(stats.ok) << stats.error;
  print("linearised, k = 1e7, 50 ms, rtol 1e-10", stats);
  EXPECT_LT(coarse[0], 1e-8) << "angles";
  EXPECT_LT(coarse[3], 1e-8) << "position";
  for (int b : {1, 2, 4}) EXPECT_LT(coarse[static_cast<std::size_t>(b)], 1e-6) << "block at " << blocks[b];
  // Two decades tighter, every state to 1e-8: CVODE converges to the exact solution.
  ReferenceOptions tight;
  tight.rtol = tight.atol_factor = 1e-12;
  const hmp::simulate::SolverStats tight_stats = solve(tight, fine);
  ASSERT_TRUE(tight_stats.ok) << tight_stats.error;
  for (int b = 0; b < kBlocks; ++b) EXPECT_LT(fine[static_cast<std::size_t>(b)], 1e-8) << "block at " << blocks[b];

  // And the drive keeps the nonlinear plant's strings taut at this stiffness (the linearisation's premise).
  const PlantTrace stiff = hmp::simulate::cvode_reference(params, kBias, drive);
  ASSERT_TRUE(stiff.ok) << stiff.error;
  print("k = 1e7, translation only, 50 ms", stiff);
  EXPECT_EQ(stiff.roots, 0);
}

// Motors 0–3 let go (duty 0) for 40 ms after 20 ms of holding, then hold again: their strings go slack and
// snap taut. Not all eight: released together, the mirror-image strings bounce against each other and the
// scene is chaotic — the root times of mirror strings drift apart from 1e-12 s to 1e-9 s within 3 ms, and
// traces at rtol 1e-12 and 1e-13 differ by 20% (measured), which no tolerance can converge.
TEST(PlantReference, ConvergesWhereStringsGoSlackAndTaut) {
  plant::PlantParams params;
  params.string.stiffness = 1e6;
  const PlantDrive drive = releasing_drive(params, 100, 0.0, 20, 60);
  ReferenceOptions coarse, fine;
  coarse.rtol = 1e-10;
  fine.rtol = 1e-11;
  const PlantTrace a = hmp::simulate::cvode_reference(params, kBias, drive, coarse);
  const PlantTrace b = hmp::simulate::cvode_reference(params, kBias, drive, fine);
  ASSERT_TRUE(a.ok) << a.error;
  ASSERT_TRUE(b.ok) << b.error;
  print("slack scene, rtol 1e-10", a);
  print("slack scene, rtol 1e-11", b);
  EXPECT_GT(a.roots, 0);
  EXPECT_GT(b.roots, 0);
  int slack_ticks = 0;
  for (const Duties& t : a.tension)
    for (double v : t) slack_ticks += v == 0;
  EXPECT_GT(slack_ticks, 0);
  const double error = relative_rms(a.string_force, b.string_force);
  std::printf("[ reference ] slack scene: %d slack string-ticks, rtol 1e-10 against 1e-11: %.3g\n", slack_ticks, error);
  EXPECT_LT(error, 1e-6);
}

// The one-tick reference from the states of a run: each tick taken again from the state the run began it
// at lands where the run did, as near as the run is exact — the plant's RK4 at 1/512 and 1/2048 of a tick,
// in a scene whose strings go slack and taut at 10⁶ N/m, the finer nearer — and it follows the drive's own
// tick, not the first.
struct SampledRun {
  std::vector<hmp::simulate::TickStart> starts;
  std::vector<plant::Vec3d> ends;
  int slack = 0;  // string-ticks
};
SampledRun sampled_rk4(plant::PlantParams params, const PlantDrive& drive, int steps_per_tick) {
  params.stepper.method = plant::Method::rk4;
  params.stepper.max_step = kTick / steps_per_tick;
  plant::Plant run(params);
  run.reset(kBias);
  SampledRun out;
  for (std::size_t k = 0; k < drive.duty.size(); ++k) {
    double d[8];
    for (int i = 0; i < 8; ++i) d[i] = drive.duty[k][static_cast<std::size_t>(i)];
    run.set_finger_anchor(drive.anchor[k]);
    if (k % 3 == 1) out.starts.push_back({k, std::vector<double>(run.state(), run.state() + run.state_size())});
    const plant::PlantOutput& o = run.step(d, drive.tick_s);
    if (k % 3 == 1) out.ends.push_back(o.string_force);
    for (int i = 0; i < 8; ++i) out.slack += (o.taut >> i & 1u) == 0;
  }
  return out;
}

TEST(PlantReference, TakesEachTickAgainFromTheStatesOfARun) {
  plant::PlantParams params;
  params.string.stiffness = 1e6;
  const PlantDrive drive = releasing_drive(params, 60, 0.05, 20, 40);
  const SampledRun coarse = sampled_rk4(params, drive, 512), fine = sampled_rk4(params, drive, 2048);
  EXPECT_GT(fine.slack, 0) << "strings must go slack for the scene to test the switches";
  const PlantTrace a = hmp::simulate::cvode_ticks(params, kBias, drive, coarse.starts);
  const PlantTrace b = hmp::simulate::cvode_ticks(params, kBias, drive, fine.starts);
  ASSERT_TRUE(a.ok && b.ok) << a.error << b.error;
  ASSERT_EQ(b.string_force.size(), fine.ends.size());
  EXPECT_GT(b.roots, 0);
  const double error_coarse = relative_rms(a.string_force, coarse.ends);
  const double error_fine = relative_rms(b.string_force, fine.ends);
  // Measured: 7.7e-4 and 1.7e-4 (RK4 loses its order across a switch inside its step).
  std::printf("[ reference ] one tick at a time against RK4 at 1/512 and 1/2048 tick: %.3g, %.3g\n", error_coarse,
              error_fine);
  EXPECT_LT(error_fine, 1e-3);
  EXPECT_LT(error_fine, error_coarse / 3);
  // Each start driven by a tick other than its own (the first tick's duties) lands elsewhere.
  std::vector<hmp::simulate::TickStart> shifted = fine.starts;
  for (hmp::simulate::TickStart& t : shifted) t.tick = 0;
  const PlantTrace wrong = hmp::simulate::cvode_ticks(params, kBias, drive, shifted);
  ASSERT_TRUE(wrong.ok) << wrong.error;
  EXPECT_GT(relative_rms(wrong.string_force, fine.ends), 100 * error_fine);

  // Bad starts: a tick the drive does not have, a state of the wrong size.
  const std::vector<hmp::simulate::TickStart> beyond{{drive.duty.size(), fine.starts.front().state}};
  const PlantTrace late = hmp::simulate::cvode_ticks(params, kBias, drive, beyond);
  EXPECT_FALSE(late.ok);
  EXPECT_NE(late.error.find("not driven"), std::string::npos) << late.error;
  const std::vector<hmp::simulate::TickStart> short_state{{0, {1.0, 2.0}}};
  const PlantTrace bad = hmp::simulate::cvode_ticks(params, kBias, drive, short_state);
  EXPECT_FALSE(bad.ok);
  EXPECT_NE(bad.error.find("2 values"), std::string::npos) << bad.error;
}

TEST(PlantReference, DrivesANanDutyAsZeroAndClampsLikeThePlant) {
  const plant::PlantParams params;
  PlantDrive nan = holding_drive(params, 10, 0.0), zero = nan, big = nan, one = nan;
  for (int k = 3; k < 6; ++k) {
    nan.duty[static_cast<std::size_t>(k)][3] = std::numeric_limits<double>::quiet_NaN();
    zero.duty[static_cast<std::size_t>(k)][3] = 0.0;
    big.duty[static_cast<std::size_t>(k)][5] = 7.0;
    one.duty[static_cast<std::size_t>(k)][5] = 1.0;
  }
  const PlantTrace tn = hmp::simulate::cvode_reference(params, kBias, nan);
  const PlantTrace tz = hmp::simulate::cvode_reference(params, kBias, zero);
  const PlantTrace tb = hmp::simulate::cvode_reference(params, kBias, big);
  const PlantTrace t1 = hmp::simulate::cvode_reference(params, kBias, one);
  ASSERT_TRUE(tn.ok && tz.ok && tb.ok && t1.ok) << tn.error << tz.error << tb.error << t1.error;
  ASSERT_EQ(tn.tension.size(), 10u);
  ASSERT_EQ(tb.tension.size(), 10u);
  for (std::size_t k = 0; k < 10; ++k) {
    EXPECT_EQ(tn.tension[k], tz.tension[k]) << "tick " << k;
    EXPECT_EQ(tb.tension[k], t1.tension[k]) << "tick " << k;
  }
  EXPECT_FALSE(tn.tension[5] == hmp::simulate::cvode_reference(params, kBias, holding_drive(params, 10, 0.0))
                                    .tension[5]);  // the NaN did change the drive
}

TEST(PlantReference, ReportsBadInputAndSolverFailureWithoutThrowing) {
  const plant::PlantParams params;
  PlantDrive drive = holding_drive(params, 5, 0.0);
  drive.anchor.pop_back();
  const PlantTrace mismatched = hmp::simulate::cvode_reference(params, kBias, drive);
  EXPECT_FALSE(mismatched.ok);
  EXPECT_FALSE(mismatched.error.empty());
  EXPECT_TRUE(mismatched.string_force.empty());

  PlantDrive no_time = holding_drive(params, 5, 0.0);
  no_time.tick_s = 0;
  const PlantTrace timeless = hmp::simulate::cvode_reference(params, kBias, no_time);
  EXPECT_FALSE(timeless.ok);
  EXPECT_FALSE(timeless.error.empty());

  // A right-hand side that is never finite: CVODE gives up, and the flag's name says why.
  hmp::simulate::SwitchedOde ode;
  ode.size = 2;
  ode.atol = {1e-10, 1e-10};
  ode.rhs = [](const double*, double* dydt) { dydt[0] = dydt[1] = std::numeric_limits<double>::quiet_NaN(); };
  std::vector<double> y{1.0, 0.0};
  const hmp::simulate::SolverStats failed = hmp::simulate::cvode_integrate(ode, y, 3, kTick, 1e-8, nullptr);
  EXPECT_FALSE(failed.ok);
  EXPECT_NE(failed.error.find("CV_"), std::string::npos) << failed.error;
  std::printf("[ reference ] failing right-hand side: %s\n", failed.error.c_str());

  // A relay, y' = −sign(y): at zero it would have to switch continually (a sliding mode), where the
  // implicit steps find no solution. The solver must come back — past the switch, or with a message
  // (measured: CV_TOO_MUCH_WORK at 0.2 ms) — rather than spin forever.
  hmp::simulate::SwitchedOde relay;
  relay.size = 1;
  relay.atol = {1e-12};
  relay.rhs = [](const double* x, double* dxdt) { dxdt[0] = x[0] > 0 ? -1.0 : 1.0; };
  relay.switches = 1;
  relay.switching = [](const double* x, double* g) { g[0] = x[0]; };
  std::vector<double> x{2e-4};
  const hmp::simulate::SolverStats chatter = hmp::simulate::cvode_integrate(relay, x, 1, kTick, 1e-10, nullptr);
  std::printf("[ reference ] relay: ok %d, %ld roots, %ld steps, y = %.3g, %s\n", chatter.ok, chatter.roots,
              chatter.steps, x[0], chatter.error.c_str());
  EXPECT_GT(chatter.steps, 0);
  if (chatter.ok)
    EXPECT_LT(std::fabs(x[0]), 1e-6);
  else
    EXPECT_NE(chatter.error.find("CV"), std::string::npos) << chatter.error;
}

}  // namespace
