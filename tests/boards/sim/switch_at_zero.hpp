#pragma once
// A mass on a spring whose law changes where its position x crosses 0, for the exponential integrator's
// tests: y = (x, v), one switch function g = x, piece 0 for x ≥ 0 and piece 1 for x < 0. A test gives
// each piece's acceleration and the states' scales.
#include <cstdint>

#include "boards/sim/plant/integrators.hpp"

namespace hmp::sim::plant {

class SwitchAtZero : public OdeSystem {
 public:
  SwitchAtZero(double x_scale, double v_scale) : x_scale_(x_scale), v_scale_(v_scale) {}
  // x'' on `piece` at position x.
  virtual double acceleration(double x, std::uint32_t piece) const = 0;

  int size() const override { return 2; }
  void derivative(const double* y, double* dydt) override {
    double g[1];
    switch_functions(y, g);
    piece_derivative(y, piece_of(g), dydt);
  }
  void piece_derivative(const double* y, std::uint32_t piece, double* dydt) override {
    dydt[0] = y[1];
    dydt[1] = acceleration(y[0], piece);
  }
  void position_rates(const double* y, double* dydt) const override { dydt[0] = y[1]; }
  bool is_position(int index) const override { return index == 0; }
  double scale(int index) const override { return index == 0 ? x_scale_ : v_scale_; }
  void project(double*) const override {}
  int switch_functions(const double* y, double* g) const override {
    g[0] = y[0];
    return 1;
  }
  std::uint32_t piece_of(const double* g) const override { return g[0] < 0 ? 1u : 0u; }

 private:
  double x_scale_, v_scale_;
};

}  // namespace hmp::sim::plant
