#include "boards/sim/plant/integrators.hpp"

#include <cmath>

#include "boards/sim/plant/exponential.hpp"

namespace hmp::sim::plant {

namespace {

using Vector = std::array<double, kMaxState>;

class ExplicitEuler final : public Integrator {
 public:
  Method method() const override { return Method::explicit_euler; }
  void step(OdeSystem& system, double* y, double h) override {
    const int n = system.size();
    system.derivative(y, d_.data());
    ++evaluations_;
    for (int i = 0; i < n; ++i) y[i] += h * d_[i];
    system.project(y);
  }

 private:
  Vector d_{};
};

// Rates first (motor currents and speeds, grip velocities) from the forces at the old positions, then the
// positions from the new rates: the mechanical part is symplectic Euler, the currents explicit Euler.
class SemiImplicitEuler final : public Integrator {
 public:
  Method method() const override { return Method::semi_implicit_euler; }
  void step(OdeSystem& system, double* y, double h) override {
    const int n = system.size();
    system.derivative(y, d_.data());
    ++evaluations_;
    for (int i = 0; i < n; ++i)
      if (!system.is_position(i)) y[i] += h * d_[i];
    system.position_rates(y, d_.data());
    for (int i = 0; i < n; ++i)
      if (system.is_position(i)) y[i] += h * d_[i];
    system.project(y);
  }

 private:
  Vector d_{};
};

class RungeKutta4 final : public Integrator {
 public:
  Method method() const override { return Method::rk4; }
  void step(OdeSystem& system, double* y, double h) override {
    system.derivative(y, k1_.data());
    rk4_step(system, y, h, k1_.data(), work_);
    evaluations_ += 4;
  }

 private:
  Vector k1_{};
  RungeKuttaWork work_;
};

// Shared by the linearly implicit methods: a numerical Jacobian J of the system's smooth_derivative()
// (forward differences, one evaluation per state) and the LU factors of W = I − γ·h·J, both kept for
// `jacobian_max_age` of simulated time or until the system's structure key changes (the LU until h changes).
class LinearlyImplicit : public Integrator {
 public:
  LinearlyImplicit(double gamma, double max_age) : gamma_(gamma), max_age_(max_age) {}
  void invalidate() override { fresh_ = false; }

 protected:
  // Call right after system.derivative(y) (the structure key describes y).
  void prepare(OdeSystem& system, const double* y, double h) {
    const int n = system.size();
    const std::uint32_t key = system.structure_key();
    const bool stale = !fresh_ || age_ >= max_age_ || n != n_ || key != key_;
    if (stale) {
      n_ = n;
      key_ = key;
      fresh_ = true;
      age_ = 0;
      system.smooth_derivative(y, f0_.data());
      for (int i = 0; i < n; ++i) tmp_[i] = y[i];
      for (int j = 0; j < n; ++j) {
        // √ε relative to the state's size (or its typical size near zero): forward-difference optimum.
        const double delta = 1.5e-8 * std::fmax(std::fabs(y[j]), system.scale(j));
        tmp_[j] = y[j] + delta;
        system.smooth_derivative(tmp_.data(), col_.data());
        tmp_[j] = y[j];
        for (int i = 0; i < n; ++i) jacobian_[i * kMaxState + j] = (col_[i] - f0_[i]) / delta;
      }
      evaluations_ += static_cast<std::uint64_t>(n + 1);
    }
    age_ += h;
    if (stale || h != factor_h_) {
      factor_h_ = h;
      factorise(-gamma_ * h);
    }
  }

  // x ← W⁻¹·x: two triangular sweeps over the nonzeros only (the plant's W is block-arrow shaped: each
  // motor's rows touch its own states and the grip's, so ~half the factors are zero). Each row's sum is
  // split in two independent partial sums, so the additions do not wait on each other. These sweeps
  // are most of a Rosenbrock step's time.
  void solve(double* x) const {
    const int n = n_;
    for (int i = 0; i < n; ++i) {
      const int p = pivot_[i];
      if (p != i) {
        const double t = x[i];
        x[i] = x[p];
        x[p] = t;
      }
    }
    for (int i = 1; i < n; ++i) x[i] -= sparse_dot(row_start_[i], row_middle_[i], x);
    for (int i = n - 1; i >= 0; --i)
      x[i] = (x[i] - sparse_dot(row_middle_[i], row_start_[i + 1], x)) * inv_diagonal_[i];
  }

  Vector tmp_{}, col_{}, f0_{};

 private:
  double sparse_dot(int begin, int end, const double* x) const {
    double s0 = 0, s1 = 0;
    int k = begin;
    for (; k + 2 <= end; k += 2) {
      s0 += value_[k] * x[column_[k]];
      s1 += value_[k + 1] * x[column_[k + 1]];
    }
    if (k < end) s0 += value_[k] * x[column_[k]];
    return s0 + s1;
  }

  // Row i's nonzeros of L (strictly lower) in [row_start_[i], row_middle_[i]), of U (strictly upper) in
  // [row_middle_[i], row_start_[i + 1]).
  void compress() {
    const int n = n_;
    int k = 0;
    for (int i = 0; i < n; ++i) {
      row_start_[i] = k;
      const double* row = &lu_[i * kMaxState];
      for (int j = 0; j < i; ++j)
        if (row[j] != 0.0) {
          value_[k] = row[j];
          column_[k] = j;
          ++k;
        }
      row_middle_[i] = k;
      for (int j = i + 1; j < n; ++j)
        if (row[j] != 0.0) {
          value_[k] = row[j];
          column_[k] = j;
          ++k;
        }
      inv_diagonal_[i] = 1.0 / row[i];
    }
    row_start_[n] = k;
  }

  // LU with partial pivoting of I + a·J (row swaps recorded LAPACK-style: row i swapped with pivot_[i]).
  void factorise(double a) {
    const int n = n_;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) lu_[i * kMaxState + j] = a * jacobian_[i * kMaxState + j] + (i == j ? 1.0 : 0.0);
    for (int k = 0; k < n; ++k) {
      int p = k;
      double best = std::fabs(lu_[k * kMaxState + k]);
      for (int i = k + 1; i < n; ++i) {
        const double v = std::fabs(lu_[i * kMaxState + k]);
        if (v > best) {
          best = v;
          p = i;
        }
      }
      pivot_[k] = p;
      if (p != k)
        for (int j = 0; j < n; ++j) {
          const double t = lu_[k * kMaxState + j];
          lu_[k * kMaxState + j] = lu_[p * kMaxState + j];
          lu_[p * kMaxState + j] = t;
        }
      const double inv = 1.0 / lu_[k * kMaxState + k];  // W = I − γhJ is never singular for a stable plant
      for (int i = k + 1; i < n; ++i) {
        double* row = &lu_[i * kMaxState];
        const double l = row[k] * inv;
        row[k] = l;
        if (l == 0.0) continue;  // the plant's Jacobian is mostly zeros: skip empty eliminations
        const double* top = &lu_[k * kMaxState];
        for (int j = k + 1; j < n; ++j) row[j] -= l * top[j];
      }
    }
    compress();
    ++factorisations_;
  }

  double gamma_;
  double max_age_;
  bool fresh_ = false;
  double age_ = 0;  // simulated time the Jacobian has been used for
  int n_ = 0;
  std::uint32_t key_ = 0;
  double factor_h_ = 0;
  std::array<double, kMaxState * kMaxState> jacobian_{};
  std::array<double, kMaxState * kMaxState> lu_{};
  std::array<int, kMaxState> pivot_{};
  std::array<double, kMaxState * kMaxState> value_{};
  std::array<int, kMaxState * kMaxState> column_{};
  std::array<int, kMaxState + 1> row_start_{};
  std::array<int, kMaxState> row_middle_{};
  Vector inv_diagonal_{};
};

class LinearImplicitEuler final : public LinearlyImplicit {
 public:
  explicit LinearImplicitEuler(double max_age) : LinearlyImplicit(1.0, max_age) {}
  Method method() const override { return Method::linear_implicit_euler; }
  void step(OdeSystem& system, double* y, double h) override {
    const int n = system.size();
    system.derivative(y, k_.data());
    ++evaluations_;
    prepare(system, y, h);
    solve(k_.data());
    for (int i = 0; i < n; ++i) y[i] += h * k_[i];
    system.project(y);
  }

 private:
  Vector k_{};
};

class Rosenbrock2 final : public LinearlyImplicit {
 public:
  explicit Rosenbrock2(double max_age) : LinearlyImplicit(kGamma, max_age) {}
  Method method() const override { return Method::rosenbrock2; }
  void step(OdeSystem& system, double* y, double h) override {
    const int n = system.size();
    system.derivative(y, k1_.data());
    ++evaluations_;
    prepare(system, y, h);
    solve(k1_.data());
    for (int i = 0; i < n; ++i) tmp_[i] = y[i] + h * k1_[i];
    system.derivative(tmp_.data(), k2_.data());
    ++evaluations_;
    for (int i = 0; i < n; ++i) k2_[i] -= 2.0 * k1_[i];
    solve(k2_.data());
    for (int i = 0; i < n; ++i) y[i] += h * (1.5 * k1_[i] + 0.5 * k2_[i]);
    system.project(y);
  }

 private:
  // Both roots of γ² − 2γ + ½ = 0 make ROS2 L-stable (R(∞) = 0). Verwer et al. take 1 + 1/√2; the smaller
  // root damps oscillations far less (|R(0.35i)| = 0.99998 against 0.965): with the strings' ~225 Hz
  // resonance near the vibration it cut the force error of the work-precision scene 12× at equal steps.
  static constexpr double kGamma = 1.0 - 0.70710678118654752440;
  Vector k1_{}, k2_{};
};

}  // namespace

std::string_view method_name(Method m) {
  switch (m) {
    case Method::explicit_euler: return "explicit_euler";
    case Method::semi_implicit_euler: return "semi_implicit_euler";
    case Method::rk4: return "rk4";
    case Method::linear_implicit_euler: return "linear_implicit_euler";
    case Method::rosenbrock2: return "rosenbrock2";
    case Method::exponential: return "exponential";
  }
  return "?";
}

double default_max_step(Method m) { return m == Method::exponential ? 1e-3 : 1.25e-4; }

bool parse_method(std::string_view name, Method& out) {
  for (Method m : kAllMethods)
    if (method_name(m) == name) {
      out = m;
      return true;
    }
  return false;
}

void rk4_step(OdeSystem& system, double* y, double h, const double* k1, RungeKuttaWork& work) {
  const int n = system.size();
  double *k2 = work.k2.data(), *k3 = work.k3.data(), *k4 = work.k4.data(), *stage = work.stage.data();
  for (int i = 0; i < n; ++i) stage[i] = y[i] + 0.5 * h * k1[i];
  system.derivative(stage, k2);
  for (int i = 0; i < n; ++i) stage[i] = y[i] + 0.5 * h * k2[i];
  system.derivative(stage, k3);
  for (int i = 0; i < n; ++i) stage[i] = y[i] + h * k3[i];
  system.derivative(stage, k4);
  for (int i = 0; i < n; ++i) y[i] += h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
  system.project(y);
}

std::unique_ptr<Integrator> make_integrator(Method method, const IntegratorOptions& options) {
  switch (method) {
    case Method::explicit_euler: return std::make_unique<ExplicitEuler>();
    case Method::semi_implicit_euler: return std::make_unique<SemiImplicitEuler>();
    case Method::rk4: return std::make_unique<RungeKutta4>();
    case Method::linear_implicit_euler: return std::make_unique<LinearImplicitEuler>(options.jacobian_max_age);
    case Method::rosenbrock2: return std::make_unique<Rosenbrock2>(options.jacobian_max_age);
    case Method::exponential: return make_exponential_integrator();
  }
  return nullptr;
}

}  // namespace hmp::sim::plant
