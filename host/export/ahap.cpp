// Apple Core Haptics pattern (.ahap), docs/exports.md. One HapticContinuous event per note (split at 30 s,
// Apple's limit for a continuous event), intensity = the note's mapped amplitude, sharpness = its mapped
// frequency placed in the mapping's range. The envelopes go into HapticIntensityControl parameter curves.
// A parameter curve is pattern-wide in Core Haptics: it scales every event playing while it runs, so the
// curves carry one control signal for the whole track, M(t) = Σ envelope_i(t) / Σ intensity_i over the
// notes sounding at t; every sounding event times M then sums to the track's envelope, overlaps included.
// M is sampled per tick, reduced to the points linear interpolation needs (within kCurveTolerance, with
// points on both sides of every note start and end, where M jumps), and cut into curves of ≤ 16 points.
#include <algorithm>
#include <cmath>

#include "host/export/json_writers.hpp"

namespace hmp::exporting {

namespace {

using nlohmann::json;

constexpr double kCurveTolerance = 0.005;  // of full scale, between a curve and M at any tick

json event(double time_s, double duration_s, double intensity, double sharpness) {
  return {{"Event",
           {{"Time", time_s},
            {"EventType", "HapticContinuous"},
            {"EventDuration", duration_s},
            {"EventParameters",
             json::array({{{"ParameterID", "HapticIntensity"}, {"ParameterValue", intensity}},
                          {{"ParameterID", "HapticSharpness"}, {"ParameterValue", sharpness}}})}}}};
}

// The ticks (from the window's start) where M needs a point: every step, both sides of each jump, and
// wherever linear interpolation between the kept points misses M by more than the tolerance.
std::vector<std::size_t> curve_points(const std::vector<double>& m, const std::vector<bool>& jump, std::size_t step) {
  std::vector<std::size_t> keep;
  for (std::size_t k = 0; k < m.size(); ++k) {
    if (k % step == 0 || jump[k] || (k + 1 < m.size() && jump[k + 1]) || k + 1 == m.size()) keep.push_back(k);
  }
  std::vector<std::size_t> out{keep.front()};
  const auto refine = [&](auto&& self, std::size_t i0, std::size_t i1) -> void {
    std::size_t worst = i0;
    double worst_err = kCurveTolerance;
    for (std::size_t k = i0 + 1; k < i1; ++k) {
      const double lin = m[i0] + (m[i1] - m[i0]) * static_cast<double>(k - i0) / static_cast<double>(i1 - i0);
      if (std::abs(lin - m[k]) > worst_err) {
        worst_err = std::abs(lin - m[k]);
        worst = k;
      }
    }
    if (worst == i0) {
      out.push_back(i1);
      return;
    }
    self(self, i0, worst);
    self(self, worst, i1);
  };
  for (std::size_t q = 0; q + 1 < keep.size(); ++q) refine(refine, keep[q], keep[q + 1]);
  return out;
}

}  // namespace

json ahap_json(const ExportSpec& spec) {
  const haptics::HapticOptions& o = *spec.opts;
  const double T = 1.0 / static_cast<double>(o.tick_hz);
  const auto step = static_cast<std::size_t>(std::max(1.0, std::round(kExportStepS * static_cast<double>(o.tick_hz))));
  json pattern = json::array();

  // The events, and per tick the summed envelope and the summed intensity of the sounding notes.
  const std::size_t ticks = spec.end_tick > spec.first_tick ? static_cast<std::size_t>(spec.end_tick - spec.first_tick) : 0;
  std::vector<double> sum_env(ticks, 0.0), sum_intensity(ticks, 0.0);
  std::vector<bool> jump(ticks + 1, false);
  for (const ExportNote& n : export_notes(spec)) {
    for (double off = 0; off < n.duration_s - 1e-12; off += kAhapMaxEventS) {
      pattern.push_back(event(n.start_s + off, std::min(kAhapMaxEventS, n.duration_s - off), n.intensity, n.sharpness));
    }
  }
  for (const haptics::HapticNote& hn : spec.track->notes) {
    const synth::Note& n = hn.note;
    const std::uint64_t a = std::max(n.start_tick, spec.first_tick);
    const std::uint64_t b = std::min(n.start_tick + n.duration_ticks, spec.end_tick);
    if (a >= b) continue;
    const envelope::Envelope env = note_envelope(*spec.track, o, n);
    const double intensity = std::clamp(static_cast<double>(n.amp_q16) / 65535.0, 0.0, 1.0);
    for (std::uint64_t k = a; k < b; ++k) {
      sum_env[k - spec.first_tick] += static_cast<double>(env.at(static_cast<std::uint32_t>(k - n.start_tick)));
      sum_intensity[k - spec.first_tick] += intensity;
    }
    jump[a - spec.first_tick] = true;
    jump[b - spec.first_tick] = true;
  }
  if (ticks > 0 && !pattern.empty()) {
    std::vector<double> m(ticks, 0.0);
    for (std::size_t k = 0; k < ticks; ++k) {
      m[k] = sum_intensity[k] > 0 ? std::clamp(sum_env[k] / sum_intensity[k], 0.0, 1.0) : 0.0;
    }
    const std::vector<std::size_t> pts = curve_points(m, jump, step);
    // Consecutive curves of ≤ 16 points; each after the first starts on the previous one's last point.
    for (std::size_t i = 0; i + 1 < pts.size();) {
      const std::size_t end = std::min(pts.size(), i + kAhapMaxCurvePoints);
      const double t0 = static_cast<double>(pts[i]) * T;
      json points = json::array();
      for (std::size_t k = i; k < end; ++k) {
        points.push_back({{"Time", static_cast<double>(pts[k]) * T - t0}, {"ParameterValue", m[pts[k]]}});
      }
      pattern.push_back({{"ParameterCurve",
                          {{"ParameterID", "HapticIntensityControl"}, {"Time", t0}, {"ParameterCurveControlPoints", std::move(points)}}}});
      i = end - 1;
    }
  }
  return {{"Version", 1.0},
          {"Metadata", {{"Project", "Haptic Music Player"}, {"Description", spec.title}, {"Created", "hmp render"}}},
          {"Pattern", std::move(pattern)}};
}

}  // namespace hmp::exporting
