// sim-linearisation (design §12): what one linearisation of the exponential integrator costs (the
// Jacobian, the matrix functions E, P, Q at every level, the switch rows), measured through the
// integrator itself: a step after invalidate() against a step on the cached linearisation, from the same
// state of the default plant held at its bias for 50 ms, at each string stiffness.
//
// Prints one JSON line per stiffness: metric recompute_us, params stiffness_n_per_m, step_us (a step on a
// cached linearisation), clock thread_cpu (best of 3, the machine being shared).
#include <algorithm>
#include <cstdio>
#include <vector>

#include "boards/sim/plant/plant.hpp"
#include "host/common/cpu_time.hpp"

namespace {

using namespace hmp::sim;

constexpr double kTick = 1e-3;

// CPU µs per step over `count` steps from y0, after invalidate() each time if `fresh`.
double step_us(plant::Integrator& integrator, plant::PlantDynamics& system, const std::vector<double>& y0, int count,
               bool fresh) {
  std::vector<double> y(y0);
  double best = 1e30;
  for (int repeat = 0; repeat < 3; ++repeat) {
    const double start = hmp::thread_cpu_seconds();
    for (int i = 0; i < count; ++i) {
      if (fresh) integrator.invalidate();
      std::copy(y0.begin(), y0.end(), y.begin());
      integrator.step(system, y.data(), kTick);
    }
    best = std::min(best, (hmp::thread_cpu_seconds() - start) / count);
  }
  return 1e6 * best;
}

}  // namespace

int main() {
  for (double k : {1e3, 1e4, 1e5, 1e6, 1e7}) {
    plant::PlantParams p;
    p.string.stiffness = k;
    plant::Plant sim(p);
    sim.reset(0.3);
    double duty[8];
    for (double& d : duty) d = sim.holding_duty(0.3);
    for (int i = 0; i < 50; ++i) sim.step(duty, kTick);
    plant::PlantDynamics system = sim.dynamics();
    const std::vector<double> y0(sim.state(), sim.state() + system.size());
    const std::unique_ptr<plant::Integrator> integrator = plant::make_integrator(plant::Method::exponential);
    const double cached = step_us(*integrator, system, y0, 2000, false);
    const double fresh = step_us(*integrator, system, y0, 300, true);
    std::printf(
        "{\"bench\":\"sim-linearisation\",\"metric\":\"recompute_us\",\"value\":%.1f,\"unit\":\"us\","
        "\"params\":{\"stiffness_n_per_m\":%g,\"step_us\":%.2f,\"clock\":\"thread_cpu\"}}\n",
        fresh - cached, k, cached);
    std::fflush(stdout);
  }
}
