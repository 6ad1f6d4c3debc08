#pragma once
// Error against run time of the plant's integrators on one scene (design §12): every integrator at every
// step size asked for, and CVODE at looser tolerances as the solver a user would pick instead, all
// against CVODE at a tight tolerance with every switch located (plant_reference.hpp). The same code serves
// the sim-work-precision benchmark (the fixed scenes) and `hmp sim --work-precision` (a user's passage).
//
// Error (force_error_rel): RMS over the ticks of |F − F_ref| over the RMS of the reference's vibration
// (F_ref minus its mean), F sampled at the end of each tick; for the string force on the grip Σ T_i u_i
// (what the device renders, with the strings' ringing in it) and for the force on the finger (what the
// user feels). Speed (realtime_factor): simulated seconds per second of this thread's CPU time, best of
// `repeats` runs, because wall time on a shared machine would measure the neighbours.
//
// Also the error of the string force's part below 1 kHz (band_force: the band a finger feels, without the
// strings' kilohertz ringing), from the plant's band_force states, for the default integrator only: the
// filter's 1 kHz pole would limit the explicit methods' stable step where the plant itself does not.
//
// The reference is run at rtol and at rtol / 2; their difference is reference_convergence. An error is
// claimed only where it is at least 10 times that (claimed()). Where strings snap chaotically (10⁶ N/m
// and more at the frame's corner) no reference converges over a second, so for the default integrator
// the error over one tick is measured too (tick_error): every kTickSampleEvery-th tick of its own run
// taken again by CVODE from the same state (cvode_ticks()), at rtol / 2 and, for its convergence, at rtol.
#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "boards/sim/plant/integrators.hpp"
#include "host/simulate/plant_reference.hpp"
#include "host/simulate/plant_scenes.hpp"

namespace hmp::simulate {

struct TraceError {
  double force = 0, finger_force = 0;
  double band_force = std::numeric_limits<double>::quiet_NaN();  // NaN where either trace has no band
};
TraceError trace_error(const PlantTrace& run, const PlantTrace& reference);

// The scene on our Plant with `method` at internal steps of at most `max_step` seconds (`band`: with the
// band_force states too); cpu_s is the thread's CPU time, rhs_evals the integrator's derivative evaluations
// (Jacobian columns included) and ok false if the plant went unstable. With
// `starts`: also the state every `every`-th tick starts from, for cvode_ticks().
PlantTrace run_plant(const PlantScene& scene, sim::plant::Method method, double max_step, bool band = false,
                     std::vector<TickStart>* starts = nullptr, int every = 1);

struct WorkPrecisionOptions {
  std::vector<sim::plant::Method> methods{std::begin(sim::plant::kAllMethods), std::end(sim::plant::kAllMethods)};
  std::vector<int> steps_per_tick{1, 2, 4, 8, 16, 32, 64, 128};
  std::vector<double> cvode_rtols{1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8};
  double reference_rtol = 1e-10;
  int repeats = 3;
  // Called before each run with what it is, how many runs are done and how many there are in all.
  std::function<void(std::string_view what, std::size_t done, std::size_t total)> progress;
};

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr int kTickSampleEvery = 5;
// The longest passage a work-precision run takes (hmp sim, the benchmark): the reference takes seconds per
// simulated second.
inline constexpr double kMaxWorkPrecisionSeconds = 20.0;

struct WorkPrecisionPoint {
  std::string integrator;   // a Method's name, or "cvode"
  int steps_per_tick = 0;   // 0 for cvode
  double rtol = 0;          // cvode only
  bool is_default = false;  // the plant's default integrator and step
  std::string failure;      // empty if stable (ours) or succeeded (cvode), else why: "unstable", or CVODE's error
  TraceError error;
  TraceError tick_error = {kNaN, kNaN, kNaN};  // the default integrator only
  double cpu_s = 0, realtime_factor = 0;
  long derivatives = 0;  // the run's derivative evaluations, Jacobian columns included (cvode's likewise)
  bool ok() const { return failure.empty(); }
};

struct WorkPrecision {
  PlantTrace reference;              // at reference_rtol / 2
  TraceError reference_convergence;  // between the reference at reference_rtol and at half of it
  TraceError tick_reference_convergence = {kNaN, kNaN, kNaN};  // the one-tick reference's, likewise
  std::string tick_reference_error;  // why the one-tick errors were not measured, if CVODE failed there
  std::vector<WorkPrecisionPoint> points;
  // Whether an error this size is resolved by the reference (≥ 10 × its convergence).
  bool claimed(double error, double convergence) const { return error >= 10.0 * convergence; }
};

// Throws std::runtime_error if the reference fails.
WorkPrecision work_precision(const PlantScene& scene, const WorkPrecisionOptions& options);

// The plant's default integrator and its steps per tick at a tick of `tick_s`.
sim::plant::Method default_method();
int default_steps_per_tick(double tick_s);

}  // namespace hmp::simulate
