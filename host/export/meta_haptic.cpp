// Meta Haptics Studio clip (.haptic): the summed signal's envelope (sum of the sounding notes' envelopes,
// clipped to full scale) as the amplitude envelope, and the loudest sounding note's mapped frequency, placed
// in the mapping's range, as the frequency envelope; both on one grid of kExportStepS (docs/exports.md).
#include <algorithm>
#include <cmath>

#include "host/export/json_writers.hpp"

namespace hmp::exporting {

nlohmann::json meta_haptic_json(const ExportSpec& spec) {
  using nlohmann::json;
  const haptics::HapticOptions& o = *spec.opts;
  const std::uint32_t hz = o.tick_hz;
  const auto step = static_cast<std::uint64_t>(std::max(1.0, std::round(kExportStepS * static_cast<double>(hz))));
  const std::uint64_t first = spec.first_tick, end = spec.end_tick;
  const std::size_t slots = end > first ? static_cast<std::size_t>((end - first - 1) / step) + 1 : 0;
  // One more point than the grid: the window's last tick, so the clip lasts exactly the window (and has
  // the two breakpoints and positive duration the spec asks for).
  std::vector<std::uint64_t> at(slots);
  for (std::size_t s = 0; s < slots; ++s) at[s] = first + s * step;
  if (slots > 0 && at.back() != end - 1) at.push_back(end - 1);
  std::vector<double> amp(at.size(), 0.0), loudest(at.size(), 0.0), freq(at.size(), -1.0);
  const double span_hz = o.ranges.f_max_hz - o.ranges.f_min_hz;
  for (const haptics::HapticNote& hn : spec.track->notes) {
    const synth::Note& n = hn.note;
    const std::uint64_t ne = n.start_tick + n.duration_ticks;
    if (ne <= first || n.start_tick >= end) continue;
    const envelope::Envelope env = note_envelope(*spec.track, o, n);
    const double sharp = span_hz > 0 ? std::clamp((hn.freq_hz - o.ranges.f_min_hz) / span_hz, 0.0, 1.0) : 0.5;
    const std::uint64_t a = std::max(n.start_tick, first), b = std::min(ne, end);
    for (std::size_t s = static_cast<std::size_t>(std::lower_bound(at.begin(), at.end(), a) - at.begin());
         s < at.size() && at[s] < b; ++s) {
      const double v = static_cast<double>(env.at(static_cast<std::uint32_t>(at[s] - n.start_tick)));
      amp[s] += v;
      if (v > loudest[s]) {
        loudest[s] = v;
        freq[s] = sharp;
      }
    }
  }
  json am = json::array(), fr = json::array();
  double last_f = 0.5;
  const double T = 1.0 / static_cast<double>(hz);
  for (std::size_t s = 0; s < at.size(); ++s) {
    // The last point stands at the window's end: the last tick's value holds through that tick.
    const double t = static_cast<double>(s + 1 == at.size() && s > 0 ? end - first : at[s] - first) * T;
    am.push_back({{"time", t}, {"amplitude", std::clamp(amp[s], 0.0, 1.0)}});
    if (freq[s] >= 0) last_f = freq[s];
    fr.push_back({{"time", t}, {"frequency", last_f}});
  }
  if (at.size() == 1) {  // a window of one tick: its value over the tick
    am.push_back({{"time", T}, {"amplitude", am[0]["amplitude"]}});
  }
  return {{"version", {{"major", 1}, {"minor", 0}, {"patch", 0}}},
          // Meta's spec asks authoring tools for editor, source (what the clip was made from: the song's
          // file) and description; names only, not the paths they were typed with.
          {"metadata",
           {{"editor", "hmp render"},
            {"source", song_file_name(spec)},
            {"project", ""},
            {"tags", json::array()},
            {"description", export_description(spec)}}},
          {"signals", {{"continuous", {{"envelopes", {{"amplitude", std::move(am)}, {"frequency", std::move(fr)}}}}}}}};
}

}  // namespace hmp::exporting
