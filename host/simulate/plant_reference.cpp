#include "host/simulate/plant_reference.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "boards/sim/plant/dynamics.hpp"
#include "boards/sim/plant/plant.hpp"
#include "host/common/cpu_time.hpp"

namespace hmp::simulate {

namespace plant = sim::plant;

namespace {

constexpr int kStrings = 8;
static_assert(spidar::kStrings == kStrings, "PlantDrive's arrays hold one entry per string");

// A root found again at (almost) the same time this many times in a row is chattering: the switching
// function sits on zero with the right-hand side pushing it back across from both sides.
constexpr int kMaxRepeatedRoots = 3;
constexpr double kSameRootTime = 1e-13;  // s
// On chattering, the span integrated with root finding off to get past the switch.
constexpr double kStepPast = 1e-9;  // s
// More roots than this in one tick is a switch that never settles: give up rather than crawl.
constexpr long kMaxRootsPerTick = 10000;
constexpr long kMaxStepsPerCall = 200000;

std::string flag_name(long flag) {
  char* name = CVodeGetReturnFlagName(flag);  // malloc'ed by SUNDIALS
  std::string out = name ? name : "CV_UNKNOWN";
  std::free(name);
  return out;
}

// One CVODE integrator with its context, vectors, matrix and linear solver; frees them all.
class Cvode {
 public:
  Cvode(const SwitchedOde& ode, double rtol) : ode_(ode), rtol_(rtol) {}
  ~Cvode() {
    if (mem_) CVodeFree(&mem_);
    if (solver_) SUNLinSolFree(solver_);
    if (matrix_) SUNMatDestroy(matrix_);
    if (atol_) N_VDestroy(atol_);
    if (y_) N_VDestroy(y_);
    if (ctx_) SUNContext_Free(&ctx_);
  }
  Cvode(const Cvode&) = delete;
  Cvode& operator=(const Cvode&) = delete;

  SolverStats run(std::vector<double>& y, int ticks, double tick_s,
                  const std::function<void(int, const double*)>& tick_end) {
    const double start = thread_cpu_seconds();
    if (setup(y)) {
      for (int k = 0; k < ticks && stats_.ok; ++k) {
        if (!tick(k, static_cast<double>(k + 1) * tick_s)) break;
        const double* data = N_VGetArrayPointer(y_);
        std::copy(data, data + ode_.size, y.begin());
        if (tick_end) tick_end(k, data);
      }
    }
    if (mem_) {  // the counters since the last restart (after a failure too: they tell where the work went)
      const bool ok = stats_.ok;
      harvest();
      stats_.ok = ok;
    }
    stats_.cpu_s = thread_cpu_seconds() - start;
    return stats_;
  }

 private:
  bool fail(const std::string& what) {
    if (stats_.ok) {
      stats_.ok = false;
      stats_.error = what;
      if (!message_.empty()) stats_.error += ": " + message_;
    }
    return false;
  }
  bool check(int flag, const char* call) {
    if (flag >= 0) return true;
    double t = t_;
    if (mem_) CVodeGetCurrentTime(mem_, &t);  // where CVODE got to (t_ is the last restart or root)
    char when[64];
    std::snprintf(when, sizeof when, " at t = %.9g s", t);
    return fail(std::string(call) + " returned " + flag_name(flag) + when);
  }

  bool setup(const std::vector<double>& y) {
    const int n = ode_.size;
    if (n <= 0 || static_cast<int>(y.size()) != n || static_cast<int>(ode_.atol.size()) != n || !ode_.rhs ||
        ode_.switches < 0 || (ode_.switches > 0 && !ode_.switching))
      return fail("inconsistent system: sizes of state, tolerances or missing functions");
    if (SUNContext_Create(nullptr, &ctx_) != 0 || !ctx_) return fail("SUNContext_Create failed");
    y_ = N_VNew_Serial(n, ctx_);
    atol_ = N_VNew_Serial(n, ctx_);
    if (!y_ || !atol_) return fail("N_VNew_Serial failed");
    std::copy(y.begin(), y.end(), N_VGetArrayPointer(y_));
    std::copy(ode_.atol.begin(), ode_.atol.end(), N_VGetArrayPointer(atol_));
    found_.assign(static_cast<std::size_t>(ode_.switches), 0);
    last_found_ = found_;
    mem_ = CVodeCreate(CV_BDF, ctx_);
    if (!mem_) return fail("CVodeCreate failed");
    matrix_ = SUNDenseMatrix(n, n, ctx_);
    if (!matrix_) return fail("SUNDenseMatrix failed");
    solver_ = SUNLinSol_Dense(y_, matrix_, ctx_);
    if (!solver_) return fail("SUNLinSol_Dense failed");
    return check(CVodeSetErrHandlerFn(mem_, &Cvode::on_error, this), "CVodeSetErrHandlerFn") &&
           check(CVodeInit(mem_, &Cvode::rhs, 0.0, y_), "CVodeInit") &&
           check(CVodeSetUserData(mem_, this), "CVodeSetUserData") &&
           check(CVodeSVtolerances(mem_, rtol_, atol_), "CVodeSVtolerances") &&
           check(CVodeSetLinearSolver(mem_, solver_, matrix_), "CVodeSetLinearSolver") &&
           check(CVodeSetMaxNumSteps(mem_, kMaxStepsPerCall), "CVodeSetMaxNumSteps") &&
           (ode_.max_step <= 0 || check(CVodeSetMaxStep(mem_, ode_.max_step), "CVodeSetMaxStep")) &&
           check(CVodeSetNoInactiveRootWarn(mem_), "CVodeSetNoInactiveRootWarn") && roots_on();
  }

  bool roots_on() {
    if (ode_.switches == 0) return true;
    return check(CVodeRootInit(mem_, ode_.switches, &Cvode::roots), "CVodeRootInit");
  }
  bool roots_off() { return ode_.switches == 0 || check(CVodeRootInit(mem_, 0, nullptr), "CVodeRootInit"); }

  // Adds the counters CVodeReInit is about to clear.
  bool harvest() {
    long steps = 0, evals = 0, jacobian_evals = 0;
    if (!check(CVodeGetNumSteps(mem_, &steps), "CVodeGetNumSteps") ||
        !check(CVodeGetNumRhsEvals(mem_, &evals), "CVodeGetNumRhsEvals") ||
        !check(CVodeGetNumLinRhsEvals(mem_, &jacobian_evals), "CVodeGetNumLinRhsEvals"))
      return false;
    stats_.steps += steps;
    stats_.rhs_evals += evals + jacobian_evals;
    return true;
  }

  // A fresh start at t_ from the current state (the right-hand side may have jumped here), up to `stop`.
  bool restart(double stop) {
    if (!harvest()) return false;
    if (ode_.project) ode_.project(N_VGetArrayPointer(y_));
    return check(CVodeReInit(mem_, t_, y_), "CVodeReInit") && check(CVodeSetStopTime(mem_, stop), "CVodeSetStopTime");
  }

  bool tick(int k, double end) {
    try {
      if (ode_.begin_tick) ode_.begin_tick(k);
    } catch (...) {
      return fail("begin_tick threw at tick " + std::to_string(k));
    }
    if (!restart(end)) return false;
    std::fill(last_found_.begin(), last_found_.end(), 0);
    long roots = 0;
    int repeats = 0;
    double last_root = -1.0;
    double roots_off_until = -1.0;  // while > t_: root finding is off to step past a chattering switch
    while (t_ < end) {
      const double target = roots_off_until > t_ ? roots_off_until : end;
      double reached = t_;
      const int flag = CVode(mem_, target, y_, &reached, CV_NORMAL);
      if (!check(flag, "CVode")) return false;
      t_ = reached;
      if (roots_off_until > 0 && t_ >= roots_off_until) {
        roots_off_until = -1.0;
        if (!roots_on() || (t_ < end && !restart(end))) return false;
        continue;
      }
      if (flag != CV_ROOT_RETURN) {
        if (t_ >= target) t_ = target;  // the stop time, exactly
        continue;
      }
      ++stats_.roots;
      if (++roots > kMaxRootsPerTick)
        return fail("root chattering: more than " + std::to_string(kMaxRootsPerTick) + " switches in tick " +
                    std::to_string(k) + " at t = " + std::to_string(t_) + " s");
      // Mirror-image strings may cross in the same instant and come back one by one: a repeat is the same
      // function found again.
      if (!check(CVodeGetRootInfo(mem_, found_.data()), "CVodeGetRootInfo")) return false;
      bool again = false;
      for (std::size_t i = 0; i < found_.size(); ++i) {
        again = again || (found_[i] != 0 && last_found_[i] != 0);
        last_found_[i] = found_[i];
      }
      repeats = again && t_ - last_root <= kSameRootTime ? repeats + 1 : 0;
      last_root = t_;
      if (t_ >= end) break;
      if (repeats >= kMaxRepeatedRoots) {
        // The same switch again and again: integrate a little past it without root finding.
        repeats = 0;
        roots_off_until = std::min(t_ + kStepPast, end);
        if (!roots_off() || !restart(roots_off_until)) return false;
        continue;
      }
      if (!restart(end)) return false;
    }
    if (roots_off_until > 0 && !roots_on()) return false;
    t_ = end;
    return true;
  }

  static int rhs(sunrealtype, N_Vector y, N_Vector dydt, void* user) {
    auto* self = static_cast<Cvode*>(user);
    try {
      self->ode_.rhs(N_VGetArrayPointer(y), N_VGetArrayPointer(dydt));
    } catch (...) {
      return -1;  // unrecoverable: CVODE stops with CV_RHSFUNC_FAIL
    }
    const double* rates = N_VGetArrayPointer(dydt);
    for (int i = 0; i < self->ode_.size; ++i)
      if (!std::isfinite(rates[i])) return 1;  // recoverable: CVODE retries a smaller step
    return 0;
  }
  static int roots(sunrealtype, N_Vector y, sunrealtype* g, void* user) {
    auto* self = static_cast<Cvode*>(user);
    try {
      self->ode_.switching(N_VGetArrayPointer(y), g);
    } catch (...) {
      return -1;
    }
    return 0;
  }
  // CVODE's messages go into the error string instead of stderr (warnings are dropped).
  static void on_error(int code, const char*, const char* function, char* message, void* user) {
    if (code < 0) static_cast<Cvode*>(user)->message_ = std::string(function) + ": " + message;
  }

  const SwitchedOde& ode_;
  double rtol_;
  SolverStats stats_;
  std::string message_;
  double t_ = 0;
  std::vector<int> found_, last_found_;  // CVodeGetRootInfo of this root and the previous one
  SUNContext ctx_ = nullptr;
  N_Vector y_ = nullptr, atol_ = nullptr;
  SUNMatrix matrix_ = nullptr;
  SUNLinearSolver solver_ = nullptr;
  void* mem_ = nullptr;
};

}  // namespace

SolverStats cvode_integrate(const SwitchedOde& ode, std::vector<double>& y, int ticks, double tick_s, double rtol,
                            const std::function<void(int tick, const double* y)>& tick_end) {
  if (!(tick_s > 0) || ticks < 0 || !(rtol > 0)) {
    SolverStats bad;
    bad.ok = false;
    bad.error = "invalid tick length, tick count or tolerance";
    return bad;
  }
  try {
    Cvode solver(ode, rtol);
    return solver.run(y, ticks, tick_s, tick_end);
  } catch (const std::exception& e) {  // allocation, or a callback of the caller's
    SolverStats bad;
    bad.ok = false;
    bad.error = std::string("exception: ") + e.what();
    return bad;
  } catch (...) {
    SolverStats bad;
    bad.ok = false;
    bad.error = "exception from a callback";
    return bad;
  }
}

namespace {

// The plant's equations for CVODE, driven by `drive` from its tick start_at() on (0 at first), sampled
// into a trace at the end of each tick.
class PlantOde {
 public:
  PlantOde(const plant::PlantDynamics& dynamics, const PlantDrive& drive, const plant::PlantParams& params,
           const ReferenceOptions& options)
      : dynamics_(dynamics), drive_(drive), band_(params.scene.band_force) {
    const int n = dynamics_.size();
    const double supply = params.motor.drive.supply_voltage;
    ode_.size = n;
    for (int i = 0; i < n; ++i) ode_.atol.push_back(options.atol_factor * dynamics_.scale(i));
    ode_.begin_tick = [this, supply](int k) {
      const std::size_t tick = first_ + static_cast<std::size_t>(k);
      const auto& duty = drive_.duty[tick];
      for (int i = 0; i < kStrings; ++i) {
        double d = duty[static_cast<std::size_t>(i)];
        if (!std::isfinite(d)) d = 0;  // as Plant::step drives an invalid duty
        dynamics_.set_voltage(i, std::clamp(d, -1.0, 1.0) * supply);
      }
      dynamics_.set_finger_anchor(drive_.anchor[tick]);
    };
    ode_.rhs = [this](const double* state, double* dydt) { dynamics_.derivative(state, dydt); };
    ode_.switches = plant::kMaxSwitches;
    ode_.switching = [this](const double* state, double* g) { dynamics_.switch_functions(state, g); };
    ode_.project = [this](double* state) { dynamics_.project(state); };
    ode_.max_step = options.max_step;
  }
  PlantOde(const PlantOde&) = delete;
  PlantOde& operator=(const PlantOde&) = delete;

  // Integrates `ticks` ticks from y, appending each tick's end to `trace`; the solver's counters summed
  // into it.
  bool run(std::vector<double>& y, int ticks, double rtol, PlantTrace& trace) {
    const auto sample = [&](int, const double* state) {
      plant::PlantForces f;
      dynamics_.evaluate(state, f);
      trace.string_force.push_back(f.string_force);
      trace.finger_force.push_back(f.finger_force);
      if (band_) trace.band_string_force.push_back(dynamics_.band_force(state));
      std::array<double, 8> t{};
      std::copy(f.tension, f.tension + kStrings, t.begin());
      trace.tension.push_back(t);
    };
    const SolverStats stats = cvode_integrate(ode_, y, ticks, drive_.tick_s, rtol, sample);
    trace.steps += stats.steps;
    trace.rhs_evals += stats.rhs_evals;
    trace.roots += stats.roots;
    trace.cpu_s += stats.cpu_s;
    if (!stats.ok) {
      trace.ok = false;
      trace.error = stats.error;
    }
    return stats.ok;
  }
  void start_at(std::size_t first) { first_ = first; }

 private:
  plant::PlantDynamics dynamics_;
  const PlantDrive& drive_;
  bool band_;
  std::size_t first_ = 0;
  SwitchedOde ode_;
};

std::string drive_error(const PlantDrive& drive, const ReferenceOptions& options) {
  if (drive.anchor.size() != drive.duty.size())
    return "drive: " + std::to_string(drive.duty.size()) + " duty entries but " + std::to_string(drive.anchor.size()) +
           " anchors";
  if (!(options.atol_factor > 0)) return "atol_factor must be positive";
  return {};
}

}  // namespace

PlantTrace cvode_reference(const plant::PlantParams& params, double bias_tension, const PlantDrive& drive,
                           const ReferenceOptions& options) {
  PlantTrace trace;
  trace.error = drive_error(drive, options);
  if (!trace.error.empty()) {
    trace.ok = false;
    return trace;
  }
  try {
    plant::Plant reference(params);
    reference.reset(bias_tension);
    std::vector<double> y(reference.state(), reference.state() + reference.state_size());
    const std::size_t ticks = drive.duty.size();
    trace.string_force.reserve(ticks);
    trace.finger_force.reserve(ticks);
    trace.tension.reserve(ticks);
    PlantOde ode(reference.dynamics(), drive, params, options);
    ode.run(y, static_cast<int>(ticks), options.rtol, trace);
  } catch (const std::exception& e) {
    trace.ok = false;
    trace.error = std::string("exception: ") + e.what();
  }
  return trace;
}

PlantTrace cvode_ticks(const plant::PlantParams& params, double bias_tension, const PlantDrive& drive,
                       const std::vector<TickStart>& starts, const ReferenceOptions& options) {
  PlantTrace trace;
  trace.error = drive_error(drive, options);
  for (const TickStart& s : starts)
    if (trace.error.empty() && s.tick >= drive.duty.size())
      trace.error = "tick " + std::to_string(s.tick) + " not driven";
  if (!trace.error.empty()) {
    trace.ok = false;
    return trace;
  }
  try {
    plant::Plant plant(params);
    plant.reset(bias_tension);  // the strings' free lengths
    PlantOde ode(plant.dynamics(), drive, params, options);
    for (const TickStart& s : starts) {
      if (s.state.size() != static_cast<std::size_t>(plant.state_size())) {
        trace.ok = false;
        trace.error = "tick " + std::to_string(s.tick) + ": a state of " + std::to_string(s.state.size()) +
                      " values, the plant has " + std::to_string(plant.state_size());
        break;
      }
      std::vector<double> y = s.state;
      ode.start_at(s.tick);
      if (!ode.run(y, 1, options.rtol, trace)) break;
    }
  } catch (const std::exception& e) {
    trace.ok = false;
    trace.error = std::string("exception: ") + e.what();
  }
  return trace;
}

}  // namespace hmp::simulate
