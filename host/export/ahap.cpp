// Apple Core Haptics pattern (.ahap), docs/exports.md. One HapticContinuous event per note (split at 30 s,
// Apple's limit for a continuous event), sharpness = its mapped frequency placed in the mapping's range.
// Core Haptics' intensity is quadratic, not linear: the vibration's amplitude goes as the square of the
// intensity (Meta's and Lofelt's .haptic → .ahap converters write intensity = √amplitude for this reason).
// So an event's HapticIntensity is √(the note's mapped amplitude), and the envelopes go into
// HapticIntensityControl parameter curves whose values are square roots too: a curve value multiplies the
// event's intensity, so √a · √M played squares back to a · M.
// A parameter curve is pattern-wide in Core Haptics: it scales every event playing while it runs, so the
// curves carry one control signal for the whole track, M(t) = Σ envelope_i(t) / Σ amplitude_i over the
// notes sounding at t; every sounding event, (√amplitude_i · √M)² = amplitude_i · M, then sums to the
// track's envelope, overlaps included. √M is sampled per tick, reduced to the points linear interpolation
// needs (the interpolated value squared stays within kCurveTolerance of M, with points on both sides of
// every note start and end, where M jumps), and cut into curves of ≤ 16 points. The curves end where the
// last event ends.
#include <algorithm>
#include <cmath>

#include "host/export/json_writers.hpp"

namespace hmp::exporting {

namespace {

using nlohmann::json;

constexpr double kCurveTolerance = 0.005;  // of full scale, between a curve (squared) and M at any tick

json event(double time_s, double duration_s, double intensity, double sharpness) {
  return {{"Event",
           {{"Time", time_s},
            {"EventType", "HapticContinuous"},
            {"EventDuration", duration_s},
            {"EventParameters", json::array({{{"ParameterID", "HapticIntensity"}, {"ParameterValue", intensity}},
                                             {{"ParameterID", "HapticSharpness"}, {"ParameterValue", sharpness}}})}}}};
}

// The ticks (from the window's start) where the curve c = √M needs a point: every step, both sides of each
// jump, and wherever linear interpolation of c between the kept points, squared, misses M = c² by more than
// the tolerance (the error in amplitude, which is what a player feels).
std::vector<std::size_t> curve_points(const std::vector<double>& c, const std::vector<bool>& jump, std::size_t step) {
  std::vector<std::size_t> keep;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (k % step == 0 || jump[k] || (k + 1 < c.size() && jump[k + 1]) || k + 1 == c.size()) keep.push_back(k);
  }
  std::vector<std::size_t> out{keep.front()};
  const auto refine = [&](auto&& self, std::size_t i0, std::size_t i1) -> void {
    std::size_t worst = i0;
    double worst_err = kCurveTolerance;
    for (std::size_t k = i0 + 1; k < i1; ++k) {
      const double lin = c[i0] + (c[i1] - c[i0]) * static_cast<double>(k - i0) / static_cast<double>(i1 - i0);
      const double err = std::abs(lin * lin - c[k] * c[k]);
      if (err > worst_err) {
        worst_err = err;
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

  // The events, and per tick the summed envelope and the summed amplitude of the sounding notes.
  const std::size_t ticks =
      spec.end_tick > spec.first_tick ? static_cast<std::size_t>(spec.end_tick - spec.first_tick) : 0;
  std::vector<double> sum_env(ticks, 0.0), sum_amp(ticks, 0.0);
  std::vector<bool> jump(ticks + 1, false);
  for (const ExportNote& n : export_notes(spec)) {
    const double intensity = std::sqrt(n.amplitude);  // Core Haptics' quadratic intensity
    for (double off = 0; off < n.duration_s - 1e-12; off += kAhapMaxEventS) {
      pattern.push_back(event(n.start_s + off, std::min(kAhapMaxEventS, n.duration_s - off), intensity, n.sharpness));
    }
  }
  std::size_t last_end = 0;  // ticks from the window's start to the end of the last sounding note
  for (const haptics::HapticNote& hn : spec.track->notes) {
    const synth::Note& n = hn.note;
    const std::uint64_t a = std::max(n.start_tick, spec.first_tick);
    const std::uint64_t b = std::min(n.start_tick + n.duration_ticks, spec.end_tick);
    if (a >= b) continue;
    const envelope::Envelope env = note_envelope(*spec.track, o, n);
    const double amplitude = std::clamp(static_cast<double>(n.amp_q16) / 65535.0, 0.0, 1.0);
    for (std::uint64_t k = a; k < b; ++k) {
      sum_env[k - spec.first_tick] += static_cast<double>(env.at(static_cast<std::uint32_t>(k - n.start_tick)));
      sum_amp[k - spec.first_tick] += amplitude;
    }
    jump[a - spec.first_tick] = true;
    jump[b - spec.first_tick] = true;
    last_end = std::max(last_end, static_cast<std::size_t>(b - spec.first_tick));
  }
  if (last_end > 0 && !pattern.empty()) {
    // c = √M per tick up to the last note's end, plus one point at that end: the last tick's value holds
    // through that tick, so the curves end exactly where the last event does.
    std::vector<double> c(last_end + 1, 0.0);
    for (std::size_t k = 0; k < last_end; ++k) {
      c[k] = sum_amp[k] > 0 ? std::sqrt(std::clamp(sum_env[k] / sum_amp[k], 0.0, 1.0)) : 0.0;
    }
    c[last_end] = c[last_end - 1];
    const std::vector<std::size_t> pts = curve_points(c, jump, step);
    // Consecutive curves of ≤ 16 points; each after the first starts on the previous one's last point.
    for (std::size_t i = 0; i + 1 < pts.size();) {
      const std::size_t end = std::min(pts.size(), i + kAhapMaxCurvePoints);
      const double t0 = static_cast<double>(pts[i]) * T;
      json points = json::array();
      for (std::size_t k = i; k < end; ++k) {
        points.push_back({{"Time", static_cast<double>(pts[k]) * T - t0}, {"ParameterValue", c[pts[k]]}});
      }
      pattern.push_back({{"ParameterCurve",
                          {{"ParameterID", "HapticIntensityControl"},
                           {"Time", t0},
                           {"ParameterCurveControlPoints", std::move(points)}}}});
      i = end - 1;
    }
  }
  return {{"Version", 1.0},
          {"Metadata",
           {{"Project", "Haptic Music Player"}, {"Description", export_description(spec)}, {"Created", "hmp render"}}},
          {"Pattern", std::move(pattern)}};
}

}  // namespace hmp::exporting
