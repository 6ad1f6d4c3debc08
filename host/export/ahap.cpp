// Apple Core Haptics pattern (.ahap): one HapticContinuous event per note (split at 30 s), intensity =
// mapped amplitude, sharpness = mapped frequency in the mapping's range; the note's envelope as
// HapticIntensityControl parameter curves of at most 16 points each (docs/exports.md).
#include <algorithm>
#include <cmath>

#include "host/export/json_writers.hpp"

namespace hmp::exporting {

namespace {

using nlohmann::json;

json event(double time_s, double duration_s, double intensity, double sharpness) {
  return {{"Event",
           {{"Time", time_s},
            {"EventType", "HapticContinuous"},
            {"EventDuration", duration_s},
            {"EventParameters",
             json::array({{{"ParameterID", "HapticIntensity"}, {"ParameterValue", intensity}},
                          {{"ParameterID", "HapticSharpness"}, {"ParameterValue", sharpness}}})}}}};
}

// Consecutive curves of ≤ 16 points; each curve after the first starts with the previous one's last point,
// so the piecewise-linear shape is continuous.
void add_curves(json& pattern, double base_s, const std::vector<Breakpoint>& pts) {
  std::size_t i = 0;
  while (i < pts.size()) {
    const std::size_t end = std::min(pts.size(), i + kAhapMaxCurvePoints);
    const double t0 = pts[i].t_s;
    json points = json::array();
    for (std::size_t k = i; k < end; ++k)
      points.push_back({{"Time", pts[k].t_s - t0}, {"ParameterValue", pts[k].level}});
    pattern.push_back({{"ParameterCurve",
                        {{"ParameterID", "HapticIntensityControl"},
                         {"Time", base_s + t0},
                         {"ParameterCurveControlPoints", std::move(points)}}}});
    if (end == pts.size()) break;
    i = end - 1;
  }
}

}  // namespace

json ahap_json(const ExportSpec& spec) {
  const auto step = static_cast<std::uint32_t>(
      std::max(1.0, std::round(kExportStepS * static_cast<double>(spec.opts->tick_hz))));
  json pattern = json::array();
  for (const ExportNote& n : export_notes(spec, step)) {
    // Split into pieces of at most 30 s; the curve points go with the piece they fall in.
    for (double off = 0; off < n.duration_s; off += kAhapMaxEventS) {
      const double len = std::min(kAhapMaxEventS, n.duration_s - off);
      pattern.push_back(event(n.start_s + off, len, n.intensity, n.sharpness));
      std::vector<Breakpoint> piece;
      for (const Breakpoint& b : n.envelope)
        if (b.t_s >= off && b.t_s <= off + len) piece.push_back({b.t_s - off, b.level});
      add_curves(pattern, n.start_s + off, piece);
    }
  }
  return {{"Version", 1.0},
          {"Metadata", {{"Project", "Haptic Music Player"}, {"Description", spec.title}, {"Created", "hmp render"}}},
          {"Pattern", std::move(pattern)}};
}

}  // namespace hmp::exporting
