#pragma once
// Shared pieces of the firmware-drive tests (label sim): the simulated board with the plant, driven
// through the protocol like a host (tests/firmware/host_link.hpp), and an independent measurement of a
// sinusoid's amplitude and phase in what the plant's strings do to the grip.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "boards/sim/sim_device.hpp"
#include "tests/firmware/host_link.hpp"

namespace hmp::test {

// Amplitude and phase (of a·sin(ωt + φ)) of the f-Hz component of samples (t_i, y_i), fitted by least
// squares with an offset: y ≈ c + s·sin(ωt) + k·cos(ωt). Double precision, written here.
struct Sinusoid {
  double amplitude = 0, phase = 0, offset = 0;
};
inline Sinusoid fit_sinusoid(const std::vector<double>& t, const std::vector<double>& y, double hz) {
  double m[3][3] = {}, b[3] = {};
  const double w = 2.0 * M_PI * hz;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double v[3] = {1.0, std::sin(w * t[i]), std::cos(w * t[i])};
    for (int r = 0; r < 3; ++r) {
      b[r] += v[r] * y[i];
      for (int c = 0; c < 3; ++c) m[r][c] += v[r] * v[c];
    }
  }
  for (int k = 0; k < 3; ++k)
    for (int r = k + 1; r < 3; ++r) {
      const double f = m[r][k] / m[k][k];
      for (int c = k; c < 3; ++c) m[r][c] -= f * m[k][c];
      b[r] -= f * b[k];
    }
  double x[3];
  for (int r = 2; r >= 0; --r) {
    double s = b[r];
    for (int c = r + 1; c < 3; ++c) s -= m[r][c] * x[c];
    x[r] = s / m[r][r];
  }
  return {std::hypot(x[1], x[2]), std::atan2(x[2], x[1]), x[0]};
}

// The stall duty for a tension, from design §11's motor (Kt = 21.3 mN·m/A, R = 6.5 Ω, 12 V, r = 5 mm).
inline double stall_duty(double tension) { return tension * 6.5 * 0.005 / (0.0213 * 12.0); }
// The largest t_max the drive takes (fw::Drive::max_tension_n, with the default motor): 0.8 × the
// tension a duty of 1 holds at standstill.
inline float most_tension_n() { return static_cast<float>(0.8 / stall_duty(1.0)); }

inline double wrap_angle(double a) {
  while (a > M_PI) a -= 2 * M_PI;
  while (a < -M_PI) a += 2 * M_PI;
  return a;
}

// What the plant did while observed: the string force along the direction at every observed instant,
// the extremes of every string's tension, whether every string stayed taut.
struct PlantTrace {
  std::vector<double> t, force;
  double min_tension = 1e9, max_tension = -1e9;
  bool always_taut = true;
  bool on = false;  // record only while set
  void observe(double time, const sim::plant::PlantOutput& out, double dir_y) {
    if (!on) return;
    t.push_back(time);
    force.push_back(out.string_force.y * dir_y);
    for (double tension : out.tension) {
      min_tension = std::min(min_tension, tension);
      max_tension = std::max(max_tension, tension);
    }
    always_taut = always_taut && out.taut == 0xFFu;
  }
};

// A simulated device with the plant (the drive scene: translation-only grip, a finger) and a host.
struct DriveRig {
  explicit DriveRig(std::uint32_t tick_hz, int substeps = 4, sim::SimOptions options = {})
      : dev(make_options(tick_hz, substeps, options)), host(dev) {
    dev.set_plant_observer([this](double t, const sim::plant::PlantOutput& out) { trace.observe(t, out, 1.0); });
  }
  static sim::SimOptions make_options(std::uint32_t tick_hz, int substeps, sim::SimOptions o) {
    o.tick_hz = tick_hz;
    if (!o.plant) o.plant = sim::PlantOptions{};
    o.plant->observe_substeps = substeps;
    return o;
  }
  // Hello, settings (no ramp-in: the tests look at steady vibration), play.
  void start(const protocol::Settings& s) {
    host.hello();
    host.settings(s);
    host.play();
  }
  // A constant-amplitude sine note (square envelope) from `start` for `ticks` ticks.
  void tone(std::uint64_t start, std::uint32_t ticks, double hz, double amp) {
    TestNote n;
    n.start = start;
    n.duration = ticks;
    n.hz = hz;
    n.amp = amp;
    host.long_note(n);
  }
  // Runs ticks like a live host (a Sync every 100 ms); records the commanded force (output × peak) at the
  // start of each tick's interval (plant time) when `record` is set.
  void run(std::size_t ticks, float peak, bool record) {
    const std::size_t sync_every = dev.core().tick_hz() / 10;
    for (std::size_t i = 0; i < ticks; ++i) {
      const double t0 = dev.plant()->time();
      dev.advance(1);
      if (record) {
        cmd_t.push_back(t0);
        cmd.push_back(static_cast<double>(dev.last_output()) * static_cast<double>(peak));
      }
      if (++since_sync >= sync_every) {
        host.sync(0);
        since_sync = 0;
      }
    }
  }

  sim::SimDevice dev;
  HostLink host;
  PlantTrace trace;
  std::vector<double> cmd_t, cmd;
  std::size_t since_sync = 0;
};

struct ToneResult {
  double commanded = 0, actual = 0, error = 0, lag_deg = 0, lag_ms = 0;
  double min_tension = 0, max_tension = 0;
  bool taut = false;
  std::uint32_t faults = 0;
  bool unstable = false;
};

// Plays a steady tone of `hz` at amplitude `amp` (full scale) and compares, over `window_s` after
// `settle_s`, the f-Hz component of the plant's string force along y with that of the commanded samples.
inline ToneResult measure_tone(std::uint32_t tick_hz, double hz, double amp, sim::SimOptions options = {},
                               protocol::Settings settings = exact_settings(), double settle_s = 0.2,
                               double window_s = 0.2) {
  DriveRig rig(tick_hz, tick_hz >= 10000 ? 1 : 4, options);
  rig.start(settings);
  const std::uint64_t begin = rig.dev.tick() + 20;
  const auto settle = static_cast<std::size_t>(settle_s * tick_hz),
             window = static_cast<std::size_t>(window_s * tick_hz);
  rig.tone(begin, static_cast<std::uint32_t>(settle + window + 100), hz, amp);
  rig.run(begin - rig.dev.tick() + settle, settings.peak_force_n, false);
  rig.trace.on = true;
  rig.run(window, settings.peak_force_n, true);
  const Sinusoid c = fit_sinusoid(rig.cmd_t, rig.cmd, hz), a = fit_sinusoid(rig.trace.t, rig.trace.force, hz);
  ToneResult r;
  r.commanded = c.amplitude;
  r.actual = a.amplitude;
  r.error = a.amplitude / c.amplitude - 1.0;
  const double lag = wrap_angle(c.phase - a.phase);
  r.lag_deg = lag * 180.0 / M_PI;
  r.lag_ms = lag / (2.0 * M_PI * hz) * 1e3;
  r.min_tension = rig.trace.min_tension;
  r.max_tension = rig.trace.max_tension;
  r.taut = rig.trace.always_taut;
  r.faults = rig.dev.core().faults();
  r.unstable = rig.dev.plant_unstable();
  return r;
}

inline void print_tone(const char* what, double hz, const ToneResult& r) {
  std::printf(
      "%s %5.0f Hz: commanded %.4f N, actual %.4f N, error %+.2f%%, lag %.1f deg (%.3f ms), "
      "tension %.3f..%.3f N%s\n",
      what, hz, r.commanded, r.actual, 100.0 * r.error, r.lag_deg, r.lag_ms, r.min_tension, r.max_tension,
      r.taut ? "" : ", a string went slack");
}

}  // namespace hmp::test
