// calibration: a full-scale sine on the simulated device with its plant, the grip's motion measured.
#include "host/simulate/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "boards/sim/sim_device.hpp"
#include "host/common/error.hpp"
#include "host/simulate/sim_host.hpp"
#include "shared/envelope/envelope.hpp"
#include "shared/synth/frequency.hpp"

namespace hmp::simulate {

namespace {

// What the plant did in the measured window: plant time, grip position and string force along the
// direction.
struct Trace {
  std::vector<double> t, position, force;
};

// The amplitude of the f-Hz part of samples (t, y): least squares on c + a·sin(ωt) + b·cos(ωt), the
// offset taken out (the grip sags under gravity).
double amplitude_at(const std::vector<double>& t, const std::vector<double>& y, double hz) {
  const double w = 2.0 * M_PI * hz;
  double n[3][4] = {};  // normal equations, right-hand side in column 3
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double v[3] = {1.0, std::sin(w * t[i]), std::cos(w * t[i])};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) n[r][c] += v[r] * v[c];
      n[r][3] += v[r] * y[i];
    }
  }
  for (int k = 0; k < 3; ++k) {  // Gauss–Jordan: the matrix is symmetric positive definite
    for (int r = 0; r < 3; ++r) {
      if (r == k) continue;
      const double f = n[r][k] / n[k][k];
      for (int c = k; c < 4; ++c) n[r][c] -= f * n[k][c];
    }
  }
  return std::hypot(n[1][3] / n[1][1], n[2][3] / n[2][2]);
}

// Hello, Settings (no ramp-in: the set-up looks at the steady vibration only), Play, then one note of
// `ticks` at full scale with the square envelope (constant amplitude). Returns its start tick.
std::uint64_t play_tone(SimHost& host, const sim::SimDevice& dev, const CalibrationSetup& setup, double hz,
                        double peak_force_n, std::uint64_t ticks) {
  host.send(protocol::make(protocol::Type::hello, 0));
  protocol::Message m = protocol::make(protocol::Type::settings, 0);
  m.settings.peak_force_n = static_cast<float>(peak_force_n);
  for (std::size_t i = 0; i < 3; ++i) m.settings.direction[i] = static_cast<float>(setup.direction[i]);
  m.settings.ramp_in_ms = 0;
  host.send(m);
  m = protocol::make(protocol::Type::transport, 0);
  m.transport.op = protocol::TransportOp::play;
  host.send(m);
  m = protocol::make(protocol::Type::long_note, 0);
  m.long_note.preset = static_cast<std::uint8_t>(envelope::Preset::square);
  m.long_note.start_tick = dev.tick() + 20;  // time for the reports to arrive
  m.long_note.duration_ticks = static_cast<std::uint32_t>(ticks);
  m.long_note.freq_q20 = synth::freq_to_q20(hz);
  m.long_note.amp_q16 = synth::amp_to_q16(1.0);
  host.send(m);
  return m.long_note.start_tick;
}

}  // namespace

GripMotion measure_grip(const CalibrationSetup& setup, double hz, double peak_force_n) {
  sim::SimOptions so;
  so.tick_hz = setup.tick_hz;
  so.plant = sim::PlantOptions{};
  so.plant->params = setup.plant;
  so.plant->observe_substeps = 4;  // the grip sampled between ticks too
  sim::SimDevice dev(so);
  SimHost host(dev);

  const auto& d = setup.direction;
  const double norm = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (!(norm > 0)) throw BadInput("the vibration direction is zero");
  const double u[3] = {d[0] / norm, d[1] / norm, d[2] / norm};
  Trace trace;
  bool recording = false;
  std::uint32_t saturated_before = 0;
  dev.set_plant_observer([&](double t, const sim::plant::PlantOutput& out) {
    if (!recording) return;
    const sim::plant::Vec3d p = dev.plant()->position();
    const sim::plant::Vec3d& f = out.string_force;
    trace.t.push_back(t);
    trace.position.push_back(p.x * u[0] + p.y * u[1] + p.z * u[2]);
    trace.force.push_back(f.x * u[0] + f.y * u[1] + f.z * u[2]);
  });

  const auto settle = static_cast<std::uint64_t>(std::lround(setup.settle_s * setup.tick_hz));
  const auto window = static_cast<std::uint64_t>(std::lround(setup.window_s * setup.tick_hz));
  const std::uint64_t start = play_tone(host, dev, setup, hz, peak_force_n, settle + window + 20);

  GripMotion g;
  const std::uint64_t sync_every = std::max(1u, setup.tick_hz / 10);  // well within the 250 ms watchdog
  for (std::uint64_t n = 1; dev.tick() < start + settle + window; ++n) {
    if (!recording && dev.tick() >= start + settle) {
      recording = true;
      saturated_before = dev.core().stats().drive_saturated;
    }
    dev.advance(1);
    const double planned = std::fabs(static_cast<double>(dev.core().status().force_n));
    if (recording) g.planned_n = std::max(g.planned_n, planned);
    host.collect();
    if (n % sync_every == 0) host.send(protocol::make(protocol::Type::sync, 0));
    if (dev.plant_unstable()) throw std::runtime_error("the plant simulation went unstable");
  }
  g.hz = hz;
  g.peak_force_n = peak_force_n;
  g.displacement_m = amplitude_at(trace.t, trace.position, hz);
  g.force_n = amplitude_at(trace.t, trace.force, hz);
  g.saturated = dev.core().stats().drive_saturated != saturated_before;  // the firmware clamps
  g.faults = dev.core().faults();
  return g;
}

std::vector<double> band_frequencies() {
  std::vector<double> out;
  for (double f = kBandLowHz; f <= kBandHighHz; f += 25.0) out.push_back(f);
  return out;
}

GripMotion reach(const CalibrationSetup& setup, double hz) {
  GripMotion best = measure_grip(setup, hz, kMaxPeakForceN);
  if (best.faults == 0) return best;
  double good = 0, bad = kMaxPeakForceN;
  best = GripMotion{hz, 0.0};
  while (bad - good > 0.01 * bad) {
    const double mid = 0.5 * (good + bad);
    const GripMotion g = measure_grip(setup, hz, mid);
    if (g.faults != 0) {
      bad = mid;
      continue;
    }
    good = mid;
    if (g.displacement_m > best.displacement_m) best = g;
  }
  return best;
}

std::vector<GripMotion> reach_band(const CalibrationSetup& setup) {
  std::vector<GripMotion> out;
  for (double f : band_frequencies()) out.push_back(reach(setup, f));
  return out;
}

Calibration calibrate(const CalibrationSetup& setup, double hz, double target_m, double tolerance) {
  Calibration c;
  double force = 1.0;  // a first look
  for (int i = 0; i < 8; ++i) {
    const GripMotion g = measure_grip(setup, hz, force);
    c.steps.push_back(g);
    c.peak_force_n = force;
    const double ratio = g.displacement_m / target_m;
    if (g.faults == 0 && std::fabs(ratio - 1.0) <= tolerance) {
      c.reached = true;
      return c;
    }
    // A fault means too much force: the next try is capped by the reach.
    double next = g.faults == 0 && ratio > 0 ? force / ratio : 2 * kMaxPeakForceN;
    if (next > (c.limit ? c.limit->peak_force_n : kMaxPeakForceN)) {
      if (!c.limit) c.limit = reach(setup, hz);
      if (c.limit->displacement_m < target_m * (1.0 - tolerance)) return c;
      next = std::min(next, c.limit->peak_force_n);
    }
    force = next;
  }
  return c;
}

}  // namespace hmp::simulate
