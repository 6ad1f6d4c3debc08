#include "host/simulate/work_precision.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "boards/sim/plant/plant.hpp"
#include "host/common/cpu_time.hpp"

namespace hmp::simulate {

namespace plant = sim::plant;

namespace {

double relative_error(const std::vector<plant::Vec3d>& x, const std::vector<plant::Vec3d>& ref) {
  if (ref.empty() || x.size() != ref.size()) return std::numeric_limits<double>::quiet_NaN();
  plant::Vec3d mean{};
  for (const plant::Vec3d& v : ref) mean += v;
  mean = (1.0 / static_cast<double>(ref.size())) * mean;
  double num = 0, den = 0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    num += spidar::norm2(x[k] - ref[k]);
    den += spidar::norm2(ref[k] - mean);
  }
  return den > 0 ? std::sqrt(num / den) : std::numeric_limits<double>::quiet_NaN();
}

double seconds_of(const PlantScene& scene) { return static_cast<double>(scene.drive.duty.size()) * scene.drive.tick_s; }

// The forces of `run` at the end of the ticks of `starts`, as cvode_ticks() gives them.
PlantTrace at_ticks(const PlantTrace& run, const std::vector<TickStart>& starts) {
  PlantTrace out;
  for (const TickStart& s : starts) {
    out.string_force.push_back(run.string_force[s.tick]);
    out.finger_force.push_back(run.finger_force[s.tick]);
  }
  return out;
}

// Why a run failed, never empty for a failed one (a point's ok() is that its failure is empty); "" if it ran.
std::string failure_of(const PlantTrace& run) {
  if (run.ok) return {};
  return run.error.empty() ? "failed" : run.error;
}

}  // namespace

TraceError trace_error(const PlantTrace& run, const PlantTrace& reference) {
  return {relative_error(run.string_force, reference.string_force),
          relative_error(run.finger_force, reference.finger_force),
          relative_error(run.band_string_force, reference.band_string_force)};
}

plant::Method default_method() { return plant::StepperParams{}.method; }

int default_steps_per_tick(double tick_s) {
  const double step = plant::StepperParams{}.effective_max_step();
  return std::max(1, static_cast<int>(std::ceil(tick_s / step - 1e-9)));
}

PlantTrace run_plant(const PlantScene& scene, plant::Method method, double max_step, bool band,
                     std::vector<TickStart>* starts, int every) {
  plant::PlantParams p = scene.params;
  p.stepper.method = method;
  p.stepper.max_step = max_step;
  p.scene.band_force = band;
  plant::Plant sim(p);
  sim.reset(scene.bias_tension);
  const std::size_t ticks = scene.drive.duty.size();
  PlantTrace t;
  t.string_force.reserve(ticks);
  t.finger_force.reserve(ticks);
  t.tension.reserve(ticks);
  double d[spidar::kStrings];
  const double start = thread_cpu_seconds();
  for (std::size_t k = 0; k < ticks && !sim.unstable(); ++k) {
    for (int i = 0; i < spidar::kStrings; ++i) d[i] = scene.drive.duty[k][static_cast<std::size_t>(i)];
    sim.set_finger_anchor(scene.drive.anchor[k]);
    if (starts != nullptr && k % static_cast<std::size_t>(every) == 0)
      starts->push_back({k, std::vector<double>(sim.state(), sim.state() + sim.state_size())});
    const plant::PlantOutput& out = sim.step(d, scene.drive.tick_s);
    t.string_force.push_back(out.string_force);
    t.finger_force.push_back(out.finger_force);
    if (band) t.band_string_force.push_back(out.band_string_force);
    std::array<double, 8> tension{};
    std::copy(std::begin(out.tension), std::end(out.tension), tension.begin());
    t.tension.push_back(tension);
  }
  t.cpu_s = thread_cpu_seconds() - start;
  t.rhs_evals = static_cast<long>(sim.integrator().evaluations());
  if (sim.unstable()) {
    t.ok = false;
    t.error = "unstable";
  }
  return t;
}

WorkPrecision work_precision(const PlantScene& scene, const WorkPrecisionOptions& o) {
  // The runs of our integrators: every step asked for, and the default method's own step too.
  const double tick = scene.drive.tick_s;
  const int default_steps = default_steps_per_tick(tick);
  std::vector<std::pair<plant::Method, int>> runs;
  for (plant::Method m : o.methods) {
    std::vector<int> steps = o.steps_per_tick;
    if (m == default_method() && std::find(steps.begin(), steps.end(), default_steps) == steps.end())
      steps.push_back(default_steps);
    std::sort(steps.begin(), steps.end());
    for (int n : steps) runs.emplace_back(m, n);
  }
  const bool with_default = std::any_of(runs.begin(), runs.end(), [&](const auto& r) {
    return r.first == default_method() && r.second == default_steps;
  });
  const std::size_t total = 2 + (with_default ? 1 : 0) + runs.size() + o.cvode_rtols.size();
  std::size_t done = 0;
  const auto say = [&](const std::string& what) {
    if (o.progress) o.progress(what, done, total);
    ++done;
  };
  WorkPrecision wp;
  const double seconds = seconds_of(scene);
  ReferenceOptions ro;
  ro.rtol = o.reference_rtol;
  plant::PlantParams with_band = scene.params;  // the reference carries the band states for every point
  with_band.scene.band_force = true;
  say("reference (cvode, rtol " + std::to_string(o.reference_rtol) + ")");
  const PlantTrace coarse = cvode_reference(with_band, scene.bias_tension, scene.drive, ro);
  if (!coarse.ok) throw std::runtime_error("reference: " + coarse.error);
  ro.rtol = o.reference_rtol / 2;
  say("reference (cvode, rtol / 2)");
  wp.reference = cvode_reference(with_band, scene.bias_tension, scene.drive, ro);
  if (!wp.reference.ok) throw std::runtime_error("reference: " + wp.reference.error);
  wp.reference_convergence = trace_error(coarse, wp.reference);

  for (const auto& [m, n] : runs) {
    say(std::string(plant::method_name(m)) + ", " + std::to_string(n) + " steps per tick");
    WorkPrecisionPoint p;
    p.integrator = std::string(plant::method_name(m));
    p.steps_per_tick = n;
    p.is_default = m == default_method() && n == default_steps;
    std::vector<TickStart> starts;
    PlantTrace t = run_plant(scene, m, tick / n, false, p.is_default ? &starts : nullptr, kTickSampleEvery);
    p.failure = failure_of(t);
    p.derivatives = t.rhs_evals;
    if (p.ok()) {
      p.error = trace_error(t, wp.reference);
      if (p.is_default) {
        const PlantTrace banded = run_plant(scene, m, tick / n, true);
        if (banded.ok) p.error.band_force = trace_error(banded, wp.reference).band_force;
        say("one tick at a time (cvode from the default's states)");
        ReferenceOptions to;
        to.rtol = o.reference_rtol / 2;
        const PlantTrace tight = cvode_ticks(scene.params, scene.bias_tension, scene.drive, starts, to);
        to.rtol = o.reference_rtol;
        const PlantTrace loose = cvode_ticks(scene.params, scene.bias_tension, scene.drive, starts, to);
        if (!tight.ok || !loose.ok) {
          wp.tick_reference_error = (tight.ok ? loose : tight).error;  // the run's errors stand without it
        } else {
          p.tick_error = trace_error(at_ticks(t, starts), tight);
          wp.tick_reference_convergence = trace_error(loose, tight);
        }
      }
      double cpu = t.cpu_s;
      for (int r = 1; r < o.repeats; ++r) cpu = std::min(cpu, run_plant(scene, m, tick / n).cpu_s);
      p.cpu_s = cpu;
      p.realtime_factor = cpu > 0 ? seconds / cpu : std::numeric_limits<double>::infinity();
    }
    wp.points.push_back(p);
  }
  for (double rtol : o.cvode_rtols) {
    say("cvode, rtol " + std::to_string(rtol));
    WorkPrecisionPoint p;
    p.integrator = "cvode";
    p.rtol = rtol;
    ReferenceOptions co;
    co.rtol = rtol;
    co.atol_factor = rtol;
    PlantTrace t = cvode_reference(scene.params, scene.bias_tension, scene.drive, co);
    p.failure = failure_of(t);
    p.derivatives = t.rhs_evals;
    if (p.ok()) {
      p.error = trace_error(t, wp.reference);
      p.cpu_s = t.cpu_s;
      p.realtime_factor = t.cpu_s > 0 ? seconds / t.cpu_s : std::numeric_limits<double>::infinity();
    }
    wp.points.push_back(p);
  }
  return wp;
}

}  // namespace hmp::simulate
