// sim-work-precision (design §12): error against run time for every plant integrator and step size, and the
// largest stable step of each, including the extreme cases (soft and very stiff strings, slack strings,
// saturated drive, grip near the frame edge).
//
// Scene: the plant reset to the centre with 0.3 N bias tensions, driven for 1 s by feed-forward duties
// that render a 250 Hz, 1 N vibration along y: every 1 ms tick the tension QP of shared/spidar (at the
// finger's pose) turns the force into tensions, shared/spidar's motor model turns them into stall duties.
// The duties are computed once, so every integrator sees the same input. Reference: RK4 with 1024 steps
// per tick. Error: RMS over the ticks of |F − F_ref| over the RMS of the reference's vibration
// (F_ref minus its mean), for the string force on the grip (Σ T_i u_i, what the device renders) and the
// force on the finger. Speed: simulated seconds per second of this thread's CPU time (the machine is
// shared, so wall time would measure the neighbours).
//
// Prints JSON lines (see scripts/bench). Usage: bench_sim_work_precision [--plot FILE.png] [--seconds S]
//   [--freq HZ] [--quick]
#include <cairo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "boards/sim/plant/plant.hpp"
#include "shared/spidar/motor.hpp"
#include "shared/spidar/tension.hpp"

namespace {

using namespace hmp::sim::plant;
namespace spidar = hmp::spidar;
using Duties = std::array<double, spidar::kStrings>;

constexpr double kTick = 1e-3;
constexpr double kTwoPi = 6.283185307179586476925;
constexpr int kReferenceSubsteps = 1024;

struct Options {
  double seconds = 1.0;
  double freq = 250.0;
  double amplitude = 1.0;  // N
  bool quick = false;
  std::string plot;
};

// One scene: plant parameters plus the per-tick input (duties and where the finger holds the grip).
struct Case {
  std::string name;
  PlantParams params;
  std::vector<Duties> duty;       // per 1 ms tick
  std::vector<Vec3d> anchor;      // per tick
};

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Feed-forward duties for a vibration along y rendered at the finger's anchor (the pose the firmware
// would estimate), `gain` times the swing around the bias (gain > 1 drives the duties into saturation).
void vibration_duties(Case& c, const Options& o, double gain) {
  const spidar::MotorModel<double> motor(c.params.motor.drive);
  const spidar::TensionParams<double> tp;
  spidar::TensionState warm;
  spidar::Flags ignored = 0;
  const double bias = motor.duty(tp.t_min, 0.0, ignored);
  for (std::size_t k = 0; k < c.duty.size(); ++k) {
    spidar::StringGeometry<double> g;
    spidar::compute_strings(c.params.frame, c.anchor[k], spidar::Mat3<double>::identity(), g);
    const double t = static_cast<double>(k) * kTick;
    const spidar::Vec3<double> force{0.0, o.amplitude * std::sin(kTwoPi * o.freq * t), 0.0};
    const auto r = spidar::solve_tensions(g, force, spidar::Vec3<double>{}, tp, warm);
    for (int i = 0; i < spidar::kStrings; ++i) {
      spidar::Flags f = 0;
      const double d = motor.duty(r.tension[i], 0.0, f);
      c.duty[k][static_cast<std::size_t>(i)] = bias + gain * (d - bias);  // the plant clamps to ±1
    }
  }
}

std::vector<Case> make_cases(const Options& o) {
  const auto ticks = static_cast<std::size_t>(std::lround(o.seconds / kTick));
  auto blank = [&](const char* name, double stiffness) {
    Case c;
    c.name = name;
    c.params.string.stiffness = stiffness;
    c.duty.assign(ticks, Duties{});
    c.anchor.assign(ticks, Vec3d{});
    return c;
  };
  std::vector<Case> cases;
  cases.push_back(blank("nominal", 1e4));
  vibration_duties(cases.back(), o, 1.0);
  cases.push_back(blank("soft_strings", 1e3));
  vibration_duties(cases.back(), o, 1.0);
  cases.push_back(blank("stiff_strings", 1e6));
  vibration_duties(cases.back(), o, 1.0);
  // Slack: every 100 ms the drive stops for 40 ms (currents decay, strings go slack, the grip drops onto
  // the finger), then the vibration comes back and re-tensions them with a jerk.
  cases.push_back(blank("slack", 1e4));
  vibration_duties(cases.back(), o, 1.0);
  for (std::size_t k = 0; k < ticks; ++k)
    if (k % 100 >= 60) cases.back().duty[k] = Duties{};
  cases.push_back(blank("saturation", 1e4));
  vibration_duties(cases.back(), o, 10.0);
  // Edge: the finger carries the grip over 0.3 s to 90% of the workspace box (corner of x and y in the
  // box's own axes), the vibration rendered at the finger's pose all along.
  cases.push_back(blank("frame_edge", 1e4));
  {
    Case& c = cases.back();
    const auto& f = c.params.frame;
    const Vec3d corner = f.workspace_axes * Vec3d{0.9 * f.workspace_half.x, 0.9 * f.workspace_half.y, 0.0};
    for (std::size_t k = 0; k < ticks; ++k) {
      const double s = std::min(1.0, static_cast<double>(k) * kTick / 0.3);
      c.anchor[k] = (0.5 - 0.5 * std::cos(3.14159265358979323846 * s)) * corner;
    }
    vibration_duties(c, o, 1.0);
  }
  return cases;
}

struct Trace {
  std::vector<Vec3d> string_force, finger_force;
  bool stable = true;
  double cpu = 0;  // seconds
};

// Runs a case with control ticks of `tick` seconds (the input is sampled at the tick's start) and
// internal steps of at most `step`.
Trace run(const Case& c, Method method, double step, double tick = kTick, double seconds = -1) {
  PlantParams p = c.params;
  p.stepper.method = method;
  p.stepper.max_step = step;
  Plant plant(p);
  plant.reset(0.3);
  const double total = seconds > 0 ? seconds : static_cast<double>(c.duty.size()) * kTick;
  const auto ticks = static_cast<std::size_t>(std::lround(total / tick));
  Trace t;
  t.string_force.reserve(ticks);
  t.finger_force.reserve(ticks);
  double d[spidar::kStrings];
  const double start = cpu_seconds();
  for (std::size_t k = 0; k < ticks; ++k) {
    const auto input = std::min(c.duty.size() - 1, static_cast<std::size_t>(static_cast<double>(k) * tick / kTick + 1e-9));
    for (int i = 0; i < spidar::kStrings; ++i) d[i] = c.duty[input][static_cast<std::size_t>(i)];
    plant.set_finger_anchor(c.anchor[input]);
    const PlantOutput& out = plant.step(d, tick);
    t.string_force.push_back(out.string_force);
    t.finger_force.push_back(out.finger_force);
  }
  t.cpu = cpu_seconds() - start;
  t.stable = !plant.unstable();
  return t;
}

double relative_error(const std::vector<Vec3d>& x, const std::vector<Vec3d>& ref) {
  Vec3d mean{};
  for (const Vec3d& v : ref) mean += v;
  mean = (1.0 / static_cast<double>(ref.size())) * mean;
  double num = 0, den = 0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    num += spidar::norm2(x[k] - ref[k]);
    den += spidar::norm2(ref[k] - mean);
  }
  return std::sqrt(num / den);
}

void print_line(const char* metric, double value, const char* unit, const std::string& params) {
  std::printf("{\"bench\":\"sim-work-precision\",\"metric\":\"%s\",\"value\":%.4g,\"unit\":\"%s\",\"params\":{%s}}\n",
              metric, value, unit, params.c_str());
  std::fflush(stdout);
}

std::string params_of(Method m, double step, const std::string& case_name, double freq) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "\"integrator\":\"%s\",\"step_s\":%.6g,\"case\":\"%s\",\"freq_hz\":%g,\"default\":%s",
                std::string(method_name(m)).c_str(), step, case_name.c_str(), freq,
                m == StepperParams{}.method ? "true" : "false");
  return buf;
}

// One point of the work-precision diagram.
struct Point {
  Method method;
  double step, error, cpu_per_second;
};

// Largest stable step of the grid, scanning up from the smallest; steps above the 1 ms tick run with
// control ticks of that length (the duty then changes every `step`).
struct StableStep {
  double step = 0;
  bool at_least = false;  // stable at the largest step tried
};
StableStep max_stable_step(const Case& c, Method m, const std::vector<double>& grid, double seconds) {
  StableStep best;
  for (double h : grid) {  // ascending
    const double tick = std::max(h, kTick);
    if (!run(c, m, h, tick, seconds).stable) return best;
    best.step = h;
  }
  best.at_least = true;
  return best;
}

// ---- plot ----

void draw_plot(const std::string& path, const std::vector<Point>& points, const Point& chosen) {
  const int width = 960, height = 640;
  const double left = 90, right = 230, top = 50, bottom = 70;
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, width, height);
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  // Axes: x = CPU seconds per simulated second (log), y = relative force error (log).
  const double x0 = -4.0, x1 = 0.0, y0 = -10.0, y1 = 0.0;  // decades
  const double pw = width - left - right, ph = height - top - bottom;
  auto px = [&](double v) { return left + (std::log10(v) - x0) / (x1 - x0) * pw; };
  auto py = [&](double v) { return top + (y1 - std::log10(v)) / (y1 - y0) * ph; };
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, 13);
  cairo_set_line_width(cr, 1);
  for (int d = static_cast<int>(x0); d <= static_cast<int>(x1); ++d) {
    const double x = px(std::pow(10.0, d));
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, x, top);
    cairo_line_to(cr, x, top + ph);
    cairo_stroke(cr);
    char label[32];
    std::snprintf(label, sizeof label, "1e%d", d);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_move_to(cr, x - 14, top + ph + 18);
    cairo_show_text(cr, label);
  }
  for (int d = static_cast<int>(y0); d <= static_cast<int>(y1); ++d) {
    const double y = py(std::pow(10.0, d));
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, left, y);
    cairo_line_to(cr, left + pw, y);
    cairo_stroke(cr);
    char label[32];
    std::snprintf(label, sizeof label, "1e%d", d);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_move_to(cr, left - 44, y + 4);
    cairo_show_text(cr, label);
  }
  // Targets: 1% error, 50× real time.
  cairo_set_source_rgb(cr, 0.8, 0.1, 0.1);
  const double dashes[] = {6, 4};
  cairo_set_dash(cr, dashes, 2, 0);
  cairo_move_to(cr, left, py(0.01));
  cairo_line_to(cr, left + pw, py(0.01));
  cairo_move_to(cr, px(1.0 / 50), top);
  cairo_line_to(cr, px(1.0 / 50), top + ph);
  cairo_stroke(cr);
  cairo_set_dash(cr, nullptr, 0, 0);
  cairo_move_to(cr, left + 6, py(0.01) - 6);
  cairo_show_text(cr, "1% error");
  cairo_move_to(cr, px(1.0 / 50) + 6, top + 16);
  cairo_show_text(cr, "50x real time");

  const double colours[][3] = {{0.85, 0.55, 0.0}, {0.55, 0.3, 0.75}, {0.1, 0.55, 0.2}, {0.45, 0.45, 0.45}, {0.1, 0.3, 0.85}};
  int legend = 0;
  for (Method m : kAllMethods) {
    const double* c = colours[static_cast<int>(m)];
    cairo_set_source_rgb(cr, c[0], c[1], c[2]);
    cairo_set_line_width(cr, 2);
    bool first = true;
    for (const Point& p : points) {
      if (p.method != m || p.error <= 0 || p.cpu_per_second <= 0) continue;
      const double x = std::clamp(px(p.cpu_per_second), left, left + pw);
      const double y = std::clamp(py(p.error), top, top + ph);
      if (first) cairo_move_to(cr, x, y); else cairo_line_to(cr, x, y);
      first = false;
    }
    cairo_stroke(cr);
    for (const Point& p : points) {
      if (p.method != m || p.error <= 0 || p.cpu_per_second <= 0) continue;
      cairo_new_sub_path(cr);
      cairo_arc(cr, std::clamp(px(p.cpu_per_second), left, left + pw), std::clamp(py(p.error), top, top + ph), 3.5, 0, kTwoPi);
      cairo_fill(cr);
    }
    const double ly = top + 20 + 22 * legend++;
    cairo_rectangle(cr, left + pw + 16, ly - 9, 18, 10);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_move_to(cr, left + pw + 40, ly);
    const std::string name = std::string(method_name(m)) + (m == StepperParams{}.method ? " (default)" : "");
    cairo_show_text(cr, name.c_str());
  }
  // Ring around the default configuration.
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, 1.5);
  cairo_new_path(cr);
  cairo_arc(cr, px(chosen.cpu_per_second), py(chosen.error), 8, 0, kTwoPi);
  cairo_stroke(cr);
  cairo_move_to(cr, left + pw + 16, top + 20 + 22 * legend + 10);
  cairo_show_text(cr, "ring: default step");
  cairo_move_to(cr, left + pw + 16, top + 20 + 22 * legend + 30);
  cairo_show_text(cr, "points: 1, 2, 4, ... steps/tick");

  cairo_set_font_size(cr, 15);
  cairo_move_to(cr, left, 30);
  cairo_show_text(cr, "Plant simulator work-precision: 250 Hz, 1 N vibration, 1 s, string force on the grip");
  cairo_set_font_size(cr, 13);
  cairo_move_to(cr, left + pw / 2 - 150, height - 25);
  cairo_show_text(cr, "CPU seconds per simulated second (log)");
  cairo_save(cr);
  cairo_move_to(cr, 24, top + ph / 2 + 90);
  cairo_rotate(cr, -kTwoPi / 4);
  cairo_show_text(cr, "relative force error (RMS, log)");
  cairo_restore(cr);
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_rectangle(cr, left, top, pw, ph);
  cairo_stroke(cr);
  cairo_destroy(cr);
  const cairo_status_t status = cairo_surface_write_to_png(surface, path.c_str());
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS) std::fprintf(stderr, "error: cannot write %s\n", path.c_str());
  else std::fprintf(stderr, "wrote %s\n", path.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--plot" && i + 1 < argc) o.plot = argv[++i];
    else if (a == "--seconds" && i + 1 < argc) o.seconds = std::atof(argv[++i]);
    else if (a == "--freq" && i + 1 < argc) o.freq = std::atof(argv[++i]);
    else if (a == "--quick") o.quick = true;
    else {
      std::fprintf(stderr, "usage: %s [--plot FILE.png] [--seconds S] [--freq HZ] [--quick]\n", argv[0]);
      return 2;
    }
  }
  if (o.quick) o.seconds = std::min(o.seconds, 0.2);
  const std::vector<Case> cases = make_cases(o);
  const Method default_method = StepperParams{}.method;
  const double default_step = StepperParams{}.max_step;

  // Work-precision on the nominal case.
  const Case& nominal = cases.front();
  std::fprintf(stderr, "reference: RK4, %d steps per tick\n", kReferenceSubsteps);
  const Trace ref = run(nominal, Method::rk4, kTick / kReferenceSubsteps);
  const Trace half = run(nominal, Method::rk4, kTick / (kReferenceSubsteps / 2));
  char ref_params[160];
  std::snprintf(ref_params, sizeof ref_params,
                "\"integrator\":\"rk4\",\"step_s\":%.6g,\"case\":\"nominal\",\"against\":\"rk4 at half the step\"",
                kTick / kReferenceSubsteps);
  print_line("reference_error_rel", relative_error(half.string_force, ref.string_force), "ratio", ref_params);
  std::vector<Point> points;
  Point chosen{default_method, default_step, 0, 0};
  const int max_substeps = o.quick ? 32 : 128;
  for (Method m : kAllMethods) {
    for (int n = 1; n <= max_substeps; n *= 2) {
      const double h = kTick / n;
      // Best of three for the time (the error is deterministic).
      Trace t = run(nominal, m, h);
      if (!t.stable) continue;
      for (int rep = 0; rep < 2; ++rep) t.cpu = std::min(t.cpu, run(nominal, m, h).cpu);
      const std::string params = params_of(m, h, nominal.name, o.freq);
      const double err = relative_error(t.string_force, ref.string_force);
      const double rt = o.seconds / t.cpu;
      print_line("force_error_rel", err, "ratio", params);
      print_line("finger_force_error_rel", relative_error(t.finger_force, ref.finger_force), "ratio", params);
      print_line("realtime_factor", rt, "x", params + ",\"clock\":\"thread_cpu\"");
      points.push_back({m, h, err, t.cpu / o.seconds});
      if (m == default_method && std::fabs(h - default_step) < 1e-12) chosen = points.back();
    }
  }
  if (chosen.error == 0) {  // the default step is not on the 2^-k grid: measure it too
    Trace t = run(nominal, default_method, default_step);
    for (int rep = 0; rep < 2; ++rep) t.cpu = std::min(t.cpu, run(nominal, default_method, default_step).cpu);
    chosen = {default_method, default_step, relative_error(t.string_force, ref.string_force), t.cpu / o.seconds};
    const std::string params = params_of(default_method, default_step, nominal.name, o.freq);
    print_line("force_error_rel", chosen.error, "ratio", params);
    print_line("realtime_factor", o.seconds / t.cpu, "x", params + ",\"clock\":\"thread_cpu\"");
  }

  // Every case: the default's error against its step, and each integrator's largest stable step.
  std::vector<double> grid;
  for (int n : {256, 192, 128, 96, 64, 48, 32, 24, 16, 12, 10, 8, 6, 5, 4, 3, 2, 1}) grid.push_back(kTick / n);
  for (double h : {2e-3, 4e-3, 8e-3, 16e-3}) grid.push_back(h);
  const double stability_seconds = std::min(o.seconds, 0.5);
  for (const Case& c : cases) {
    std::fprintf(stderr, "case %s\n", c.name.c_str());
    if (&c != &nominal) {  // the default integrator's error against its step in this case
      const Trace cref = run(c, Method::rk4, kTick / kReferenceSubsteps);
      for (int n = 1; n <= max_substeps && cref.stable; n *= 2) {
        const Trace t = run(c, default_method, kTick / n);
        const std::string params = params_of(default_method, kTick / n, c.name, o.freq);
        if (!t.stable) continue;
        print_line("force_error_rel", relative_error(t.string_force, cref.string_force), "ratio", params);
        print_line("finger_force_error_rel", relative_error(t.finger_force, cref.finger_force), "ratio", params);
      }
    }
    for (Method m : kAllMethods) {
      const StableStep s = max_stable_step(c, m, grid, stability_seconds);
      std::string params = params_of(m, s.step, c.name, o.freq);
      params += s.at_least ? ",\"bound\":\"at_least\"" : ",\"bound\":\"grid\"";
      print_line("max_stable_step_s", s.step, "s", params);
    }
  }
  if (!o.plot.empty()) draw_plot(o.plot, points, chosen);
  return 0;
}
