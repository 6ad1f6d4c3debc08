#pragma once
// An independent reference for the plant simulator (boards/sim/plant/): the same equations integrated by
// SUNDIALS CVODE (variable-order BDF, Newton with a dense difference-quotient Jacobian) to tight
// tolerances, with every discontinuity of the right-hand side located and restarted at:
//
//   - each control tick, where the motor voltages and the finger anchor change;
//   - each zero of a string's stretch s_i and of its spring force k·s_i + c·ṡ_i (PlantForces), where the
//     string snaps taut or goes slack — found by CVODE's root finding.
//
// Our own fixed-step integrators lose their order across those jumps; this one does not, so it is what the
// plant's accuracy is measured against (tests, benchmarks). Slow (seconds per simulated second): not for
// the real-time path.
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "boards/sim/plant/plant_params.hpp"

namespace hmp::simulate {

// The plant's input, one entry per control tick.
struct PlantDrive {
  double tick_s = 1e-3;
  std::vector<std::array<double, 8>> duty;  // clamped to ±1 like Plant::step (NaN → 0)
  std::vector<sim::plant::Vec3d> anchor;    // the finger's anchor during each tick (same size as duty)
};

// What CVODE did: its counters summed over all restarts, and whether it succeeded.
struct SolverStats {
  bool ok = true;
  std::string error;   // on failure: CVODE's flag name, the time and its message
  long steps = 0;      // internal steps
  long rhs_evals = 0;  // right-hand side evaluations, the Jacobian's difference quotients included
  long roots = 0;      // switching-function zeros located (each a restart)
  double cpu_s = 0;    // CPU time of the calling thread
};

// Sampled at the end of each tick: what Plant::step's output gives then. After a failure (ok false), the
// ticks completed before it.
struct PlantTrace : SolverStats {
  std::vector<sim::plant::Vec3d> string_force, finger_force;
  std::vector<sim::plant::Vec3d> band_string_force;  // with Scene::band_force only
  std::vector<std::array<double, 8>> tension;
};

struct ReferenceOptions {
  double rtol = 1e-10;
  double atol_factor = 1e-10;  // atol_i = atol_factor · PlantDynamics::scale(i)
  double max_step = 0;         // s; 0: unlimited (see SwitchedOde::max_step)
};

// The plant of `params`, reset as Plant(params).reset(bias_tension) does, driven by `drive`.
PlantTrace cvode_reference(const sim::plant::PlantParams& params, double bias_tension, const PlantDrive& drive,
                           const ReferenceOptions& options = {});

// One tick from a given state: the tick of the drive it is and the plant's state at its start.
struct TickStart {
  std::size_t tick = 0;
  std::vector<double> state;  // Plant::state_size() values
};

// For each start, that tick alone from its state (the one-tick reference: a run's own states, each tick
// taken again by CVODE), sampled at the tick's end; the plant as cvode_reference() makes it.
PlantTrace cvode_ticks(const sim::plant::PlantParams& params, double bias_tension, const PlantDrive& drive,
                       const std::vector<TickStart>& starts, const ReferenceOptions& options = {});

// The general form: y' = rhs(y), smooth within each tick and between zeros of the switching functions.
struct SwitchedOde {
  int size = 0;
  std::vector<double> atol;                  // per state (size entries)
  std::function<void(int tick)> begin_tick;  // sets the tick's inputs (optional)
  std::function<void(const double* y, double* dydt)> rhs;
  int switches = 0;                                           // number of switching functions
  std::function<void(const double* y, double* g)> switching;  // their values (needed when switches > 0)
  std::function<void(double* y)> project;                     // back onto the state's manifold (optional)
  // Largest internal step (0: unlimited). Root finding only sees a switch whose sign differs at the ends of
  // a step: a string that touches taut for less than a step goes unseen.
  double max_step = 0;  // s
};

// Integrates `ode` from y (size ode.size) over `ticks` ticks of tick_s seconds from t = 0, restarting at
// every tick and every switch; calls tick_end(k, y) at the end of tick k. y holds the final state.
SolverStats cvode_integrate(const SwitchedOde& ode, std::vector<double>& y, int ticks, double tick_s, double rtol,
                            const std::function<void(int tick, const double* y)>& tick_end);

}  // namespace hmp::simulate
