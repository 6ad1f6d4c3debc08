// sim-work-precision (design §12): error against run time of every plant integrator at every step size,
// and of CVODE at looser tolerances, in every scene of host/simulate/plant_scenes.hpp at every string
// stiffness from 10³ to 10⁷ N/m, against CVODE at rtol 1e-10 with every slack/taut switch located
// (host/simulate/work_precision.hpp says how error and speed are measured).
//
// Prints one JSON line per point (see scripts/bench): metric force_error_rel, with params scene,
// stiffness_n_per_m, integrator, steps_per_tick (0 for cvode, then rtol), default, ok,
// force_error_rel, finger_force_error_rel, band_force_error_rel (the string force below 1 kHz; the default
// integrator only, else null), realtime_factor, reference_convergence_force, reference_convergence_band,
// reference_convergence (the finger force's), claimed (the errors are ≥ 10 × the reference's convergence),
// and for the default integrator the errors over one tick, tick_force_error_rel and
// tick_finger_force_error_rel, with their reference's convergence tick_reference_convergence_force and
// tick_reference_convergence (else null); derivatives: the run's derivative evaluations, Jacobian columns
// included (CVODE's likewise; null where it failed); failure: why a point failed (ok false: "unstable", or
// CVODE's error), else null.
// Draws one figure per scene (finger-force error against CPU seconds per simulated second, one panel per
// stiffness) into DIR/sim-work-precision-SCENE.png.
//
// Usage: bench_sim_work_precision [--plot-dir DIR] [--seconds S] [--scenes a,b] [--stiffness k1,k2]
//   [--integrators a,b (method names or cvode)] [--steps default (the default step only)]
//   [--quick] (0.2 s, steps 1–32, the default method, rosenbrock2 and cvode only)
//   [--replot FILE.jsonl] (the figures of an earlier run's output, into --plot-dir, without simulating)
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "host/common/number_text.hpp"
#include "host/config/config.hpp"
#include "host/output/loglog_plot.hpp"
#include "host/simulate/work_precision.hpp"

namespace {

using namespace hmp;
namespace plant = sim::plant;

struct Options {
  double seconds = 1.0;
  bool quick = false;
  std::string plot_dir;
  std::vector<std::string> scenes;
  std::vector<double> stiffness{1e3, 1e4, 1e5, 1e6, 1e7};
  std::vector<std::string> integrators;  // empty: all
  std::string steps;                     // "default": only each integrator's default step
  std::string replot;                    // a run's JSON lines: draw its figures only
};

// A number from the command line: the whole text, finite, else NaN.
double parse_number(const std::string& text) {
  return finite_number(text).value_or(std::numeric_limits<double>::quiet_NaN());
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string part; std::getline(in, part, ',');)
    if (!part.empty()) out.push_back(part);
  return out;
}

// A number for JSON: null where it is not finite (an unstable run has no error). Written to the last
// digit that reads back to the same double, so that --replot draws the run's own figures.
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

void print_point(const std::string& scene, double k, const simulate::WorkPrecisionPoint& p,
                 const simulate::WorkPrecision& wp) {
  const simulate::TraceError& c = wp.reference_convergence;
  const simulate::TraceError& tc = wp.tick_reference_convergence;
  const bool ok = p.ok();
  const bool claimed = ok && wp.claimed(p.error.force, c.force) && wp.claimed(p.error.finger_force, c.finger_force);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto measured = [&](double v) { return number(ok ? v : nan); };
  const auto of_default = [&](double v) { return number(p.is_default ? v : nan); };
  const nlohmann::ordered_json params = {{"scene", scene},
                                         {"stiffness_n_per_m", k},
                                         {"integrator", p.integrator},
                                         {"steps_per_tick", p.steps_per_tick},
                                         {"rtol", p.rtol},
                                         {"default", p.is_default},
                                         {"ok", ok},
                                         {"force_error_rel", measured(p.error.force)},
                                         {"finger_force_error_rel", measured(p.error.finger_force)},
                                         {"band_force_error_rel", measured(p.error.band_force)},
                                         {"realtime_factor", measured(p.realtime_factor)},
                                         {"reference_convergence_force", number(c.force)},
                                         {"reference_convergence", number(c.finger_force)},
                                         {"reference_convergence_band", number(c.band_force)},
                                         {"claimed", claimed},
                                         {"tick_force_error_rel", number(p.tick_error.force)},
                                         {"tick_finger_force_error_rel", number(p.tick_error.finger_force)},
                                         {"tick_reference_convergence_force", of_default(tc.force)},
                                         {"tick_reference_convergence", of_default(tc.finger_force)},
                                         {"derivatives", ok ? nlohmann::json(p.derivatives) : nlohmann::json(nullptr)},
                                         {"failure", ok ? nlohmann::json(nullptr) : nlohmann::json(p.failure)},
                                         {"clock", "thread_cpu"}};
  const nlohmann::ordered_json line = {{"bench", "sim-work-precision"},
                                       {"metric", "force_error_rel"},
                                       {"value", measured(p.error.force)},
                                       {"unit", "ratio"},
                                       {"params", params}};
  std::printf("%s\n", line.dump().c_str());
  std::fflush(stdout);
}

// One point of a figure: its integrator (the default method's series labelled so), ringed at the default
// step, its CPU seconds per simulated second and its finger-force error (NaN where it has none).
output::LabelledPoint figure_point(const std::string& integrator, bool is_default, double cpu_per_second,
                                   double error) {
  const bool default_method = integrator == plant::method_name(simulate::default_method());
  return {default_method ? integrator + " (default)" : integrator, is_default, cpu_per_second, error};
}

output::LogLogPanel panel_of(double k, const std::vector<output::LabelledPoint>& points) {
  char title[64];
  std::snprintf(title, sizeof title, "k = %.0e N/m", k);
  return {title, output::series_of(points)};
}

std::vector<output::LabelledPoint> figure_points(const simulate::WorkPrecision& wp) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<output::LabelledPoint> out;
  for (const simulate::WorkPrecisionPoint& p : wp.points)
    out.push_back(figure_point(p.integrator, p.is_default, p.ok() ? 1.0 / p.realtime_factor : nan,
                               p.ok() ? p.error.finger_force : nan));
  return out;
}

void draw(const std::string& dir, const std::string& scene, const std::vector<output::LogLogPanel>& panels) {
  output::LogLogPlotSpec spec;
  spec.title = "Plant simulator work-precision, scene " + scene + ": finger force against CVODE (rtol 1e-10)";
  spec.x_label = "CPU seconds per simulated second";
  spec.y_label = "relative error of the finger force (RMS)";
  spec.x_guides = {{1.0 / 50, "50x real time"}};
  spec.y_guides = {{0.005, "0.5%"}};
  const std::string path = dir + "/sim-work-precision-" + scene + ".png";
  output::write_loglog_png(path, panels, spec, true);
  std::fprintf(stderr, "wrote %s\n", path.c_str());
}

// --replot FILE: the figures again from a run's JSON lines (no simulation). A line that is not one of
// ours is an error naming it (exit 2).
int replot(const std::string& jsonl, const std::string& dir) {
  std::ifstream in(jsonl);
  if (!in) {
    std::fprintf(stderr, "error: %s: cannot open\n", jsonl.c_str());
    return 2;
  }
  std::vector<std::string> scenes;
  std::map<std::string, std::map<double, std::vector<output::LabelledPoint>>> points;
  int line_number = 0;
  for (std::string text; std::getline(in, text);) {
    ++line_number;
    if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
    try {
      const nlohmann::json p = nlohmann::json::parse(text).at("params");
      const std::string scene = p.at("scene").get<std::string>();
      if (points.find(scene) == points.end()) scenes.push_back(scene);
      const double nan = std::numeric_limits<double>::quiet_NaN();
      const bool ok = p.at("ok").get<bool>();
      points[scene][p.at("stiffness_n_per_m").get<double>()].push_back(
          figure_point(p.at("integrator").get<std::string>(), p.at("default").get<bool>(),
                       ok ? 1.0 / p.at("realtime_factor").get<double>() : nan,
                       ok ? p.at("finger_force_error_rel").get<double>() : nan));
    } catch (const nlohmann::json::exception& e) {
      std::fprintf(stderr, "error: %s:%d: not a sim-work-precision line (%s)\n", jsonl.c_str(), line_number, e.what());
      return 2;
    }
  }
  for (const std::string& scene : scenes) {
    std::vector<output::LogLogPanel> panels;
    for (const auto& [k, p] : points[scene]) panels.push_back(panel_of(k, p));
    draw(dir, scene, panels);
  }
  return 0;
}

// One line on stderr; exit status 2.
int bad_input(const std::string& what) {
  std::fprintf(stderr, "error: %s\n", what.c_str());
  return 2;
}

std::string scene_list() {
  std::string out;
  for (std::string_view s : simulate::plant_scene_names()) out += (out.empty() ? "" : ", ") + std::string(s);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--plot-dir" && i + 1 < argc)
      o.plot_dir = argv[++i];
    else if (a == "--seconds" && i + 1 < argc) {
      o.seconds = parse_number(argv[++i]);
      if (!(o.seconds > 0 && o.seconds <= simulate::kMaxWorkPrecisionSeconds))
        return bad_input(fmt::format("--seconds {}: a number of seconds above 0, at most {:g}", argv[i],
                                     simulate::kMaxWorkPrecisionSeconds));
    } else if (a == "--scenes" && i + 1 < argc) {
      o.scenes = split(argv[++i]);
      const auto& names = simulate::plant_scene_names();
      for (const std::string& s : o.scenes)
        if (std::find(names.begin(), names.end(), s) == names.end())
          return bad_input("--scenes: unknown '" + s + "' (" + scene_list() + ")");
    } else if (a == "--stiffness" && i + 1 < argc) {
      o.stiffness.clear();
      for (const std::string& k : split(argv[++i])) {
        o.stiffness.push_back(parse_number(k));
        if (!(o.stiffness.back() > 0 && o.stiffness.back() <= config::kMaxPlantValue))
          return bad_input(
              fmt::format("--stiffness {}: a stiffness in N/m above 0, at most {:g}", k, config::kMaxPlantValue));
      }
      if (o.stiffness.empty()) return bad_input("--stiffness: no value");
    } else if (a == "--integrators" && i + 1 < argc)
      o.integrators = split(argv[++i]);
    else if (a == "--replot" && i + 1 < argc)
      o.replot = argv[++i];
    else if (a == "--steps" && i + 1 < argc) {
      o.steps = argv[++i];
      if (o.steps != "default") return bad_input("--steps " + o.steps + ": only 'default' (each default step)");
    } else if (a == "--quick")
      o.quick = true;
    else {
      std::fprintf(stderr,
                   "usage: %s [--plot-dir DIR] [--seconds S] [--scenes a,b] [--stiffness k1,k2] "
                   "[--integrators a,b] [--steps default] [--quick] [--replot FILE.jsonl]\n",
                   argv[0]);
      return 2;
    }
  }
  std::error_code error;
  if (!o.plot_dir.empty() && !std::filesystem::is_directory(o.plot_dir, error))
    return bad_input("--plot-dir " + o.plot_dir + ": not a directory");
  if (!o.replot.empty()) {
    try {
      return replot(o.replot, o.plot_dir.empty() ? "." : o.plot_dir);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      return 1;
    }
  }
  if (o.scenes.empty())
    for (std::string_view s : simulate::plant_scene_names()) o.scenes.emplace_back(s);
  simulate::WorkPrecisionOptions wo;
  if (o.quick) {
    o.seconds = std::min(o.seconds, 0.2);
    wo.methods = {simulate::default_method(), plant::Method::rosenbrock2};
    wo.steps_per_tick = {1, 2, 4, 8, 16, 32};
    wo.cvode_rtols = {1e-4, 1e-6};
    wo.repeats = 1;
  }
  if (!o.integrators.empty()) {
    wo.methods.clear();
    wo.cvode_rtols.clear();
    for (const std::string& n : o.integrators) {
      plant::Method m{};
      if (n == "cvode")
        wo.cvode_rtols = simulate::WorkPrecisionOptions{}.cvode_rtols;
      else if (plant::parse_method(n, m))
        wo.methods.push_back(m);
      else {
        return bad_input("--integrators: unknown '" + n + "'");
      }
    }
  }
  if (o.steps == "default") wo.steps_per_tick.clear();  // the default method's default step is always run
  try {
    for (const std::string& name : o.scenes) {
      std::vector<output::LogLogPanel> panels;
      for (double k : o.stiffness) {
        std::fprintf(stderr, "scene %s, k = %g N/m\n", name.c_str(), k);
        const simulate::PlantScene scene = simulate::make_plant_scene(name, k, o.seconds);
        const simulate::WorkPrecision wp = simulate::work_precision(scene, wo);
        for (const simulate::WorkPrecisionPoint& p : wp.points) print_point(name, k, p, wp);
        panels.push_back(panel_of(k, figure_points(wp)));
      }
      if (!o.plot_dir.empty()) draw(o.plot_dir, name, panels);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
