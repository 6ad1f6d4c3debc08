#include "boards/sim/plant/integrators.hpp"

#include <cmath>

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
    const int n = system.size();
    system.derivative(y, k1_.data());
    for (int i = 0; i < n; ++i) tmp_[i] = y[i] + 0.5 * h * k1_[i];
    system.derivative(tmp_.data(), k2_.data());
    for (int i = 0; i < n; ++i) tmp_[i] = y[i] + 0.5 * h * k2_[i];
    system.derivative(tmp_.data(), k3_.data());
    for (int i = 0; i < n; ++i) tmp_[i] = y[i] + h * k3_[i];
    system.derivative(tmp_.data(), k4_.data());
    evaluations_ += 4;
    for (int i = 0; i < n; ++i) y[i] += h / 6.0 * (k1_[i] + 2.0 * (k2_[i] + k3_[i]) + k4_[i]);
    system.project(y);
  }

 private:
  Vector k1_{}, k2_{}, k3_{}, tmp_{}, k4_{};
};

// Shared by the linearly implicit methods: a numerical Jacobian J (forward differences, one derivative
// evaluation per state) and the LU factors of W = I − γ·h·J, both kept until stale.
class LinearlyImplicit : public Integrator {
 public:
  LinearlyImplicit(double gamma, int jacobian_interval)
      : gamma_(gamma), interval_(jacobian_interval > 0 ? jacobian_interval : 1) {}
  void invalidate() override { jacobian_age_ = -1; }

 protected:
  // Call with f0 = f(y) just evaluated (so the system's structure key describes y).
  void prepare(OdeSystem& system, const double* y, const double* f0, double h) {
    const int n = system.size();
    const std::uint32_t key = system.structure_key();
    const bool stale = jacobian_age_ < 0 || jacobian_age_ >= interval_ || key != jacobian_key_ || n != n_;
    if (stale) {
      n_ = n;
      jacobian_key_ = key;
      jacobian_age_ = 0;
      for (int i = 0; i < n; ++i) tmp_[i] = y[i];
      for (int j = 0; j < n; ++j) {
        const double delta = 1.5e-8 * std::fmax(std::fabs(y[j]), system.scale(j));
        tmp_[j] = y[j] + delta;
        system.derivative(tmp_.data(), col_.data());
        tmp_[j] = y[j];
        for (int i = 0; i < n; ++i) jacobian_[i * kMaxState + j] = (col_[i] - f0[i]) / delta;
      }
      evaluations_ += static_cast<std::uint64_t>(n);
    }
    ++jacobian_age_;
    if (stale || h != factor_h_) {
      factor_h_ = h;
      factorise(-gamma_ * h);
    }
  }

  // x ← W⁻¹·x
  void solve(double* x) const {
    const int n = n_;
    for (int i = 0; i < n; ++i) {
      const int p = pivot_[i];
      if (p != i) { const double t = x[i]; x[i] = x[p]; x[p] = t; }
    }
    for (int i = 1; i < n; ++i) {
      double s = x[i];
      const double* row = &lu_[i * kMaxState];
      for (int j = 0; j < i; ++j) s -= row[j] * x[j];
      x[i] = s;
    }
    for (int i = n - 1; i >= 0; --i) {
      double s = x[i];
      const double* row = &lu_[i * kMaxState];
      for (int j = i + 1; j < n; ++j) s -= row[j] * x[j];
      x[i] = s / row[i];
    }
  }

  Vector tmp_{}, col_{};

 private:
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
        if (v > best) { best = v; p = i; }
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
    ++factorisations_;
  }

  double gamma_;
  int interval_;
  int n_ = 0;
  int jacobian_age_ = -1;
  std::uint32_t jacobian_key_ = 0;
  double factor_h_ = 0;
  std::array<double, kMaxState * kMaxState> jacobian_{};
  std::array<double, kMaxState * kMaxState> lu_{};
  std::array<int, kMaxState> pivot_{};
};

class LinearImplicitEuler final : public LinearlyImplicit {
 public:
  explicit LinearImplicitEuler(int interval) : LinearlyImplicit(1.0, interval) {}
  Method method() const override { return Method::linear_implicit_euler; }
  void step(OdeSystem& system, double* y, double h) override {
    const int n = system.size();
    system.derivative(y, k_.data());
    ++evaluations_;
    prepare(system, y, k_.data(), h);
    solve(k_.data());
    for (int i = 0; i < n; ++i) y[i] += h * k_[i];
    system.project(y);
  }

 private:
  Vector k_{};
};

class Rosenbrock2 final : public LinearlyImplicit {
 public:
  explicit Rosenbrock2(int interval) : LinearlyImplicit(kGamma, interval) {}
  Method method() const override { return Method::rosenbrock2; }
  void step(OdeSystem& system, double* y, double h) override {
    const int n = system.size();
    system.derivative(y, k1_.data());
    ++evaluations_;
    prepare(system, y, k1_.data(), h);
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
  static constexpr double kGamma = 1.0 + 0.70710678118654752440;  // 1 + 1/√2: L-stable
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
  }
  return "?";
}

bool parse_method(std::string_view name, Method& out) {
  for (Method m : kAllMethods)
    if (method_name(m) == name) {
      out = m;
      return true;
    }
  return false;
}

std::unique_ptr<Integrator> make_integrator(Method method, const IntegratorOptions& options) {
  switch (method) {
    case Method::explicit_euler: return std::make_unique<ExplicitEuler>();
    case Method::semi_implicit_euler: return std::make_unique<SemiImplicitEuler>();
    case Method::rk4: return std::make_unique<RungeKutta4>();
    case Method::linear_implicit_euler: return std::make_unique<LinearImplicitEuler>(options.jacobian_interval);
    case Method::rosenbrock2: return std::make_unique<Rosenbrock2>(options.jacobian_interval);
  }
  return nullptr;
}

}  // namespace hmp::sim::plant
