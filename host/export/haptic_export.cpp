// Note envelopes → breakpoints, and the choice of writer by extension (haptic_export.hpp).
#include "host/export/haptic_export.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "host/common/error.hpp"
#include "host/export/json_writers.hpp"
#include "host/output/output_file.hpp"
#include "shared/envelope/envelope.hpp"

namespace hmp::exporting {

namespace {

envelope::Adsr preset_of(const haptics::HapticTrack& t, std::uint8_t slot) {
  if (slot < envelope::kBuiltinCount) return envelope::builtin(static_cast<envelope::Preset>(slot));
  for (const haptics::UserPreset& u : t.uploads)
    if (u.slot == slot) return u.adsr;
  return envelope::builtin(envelope::Preset::square);
}

}  // namespace

envelope::Envelope note_envelope(const haptics::HapticTrack& t, const haptics::HapticOptions& o,
                                 const synth::Note& n) {
  envelope::Envelope env;
  env.start(preset_of(t, n.preset), static_cast<float>(n.amp_q16) / 65535.0f, n.duration_ticks,
            static_cast<float>(o.tick_hz), static_cast<float>(o.end_fade_ms));
  return env;
}

std::vector<ExportNote> export_notes(const ExportSpec& spec) {
  const haptics::HapticTrack& t = *spec.track;
  const haptics::HapticOptions& o = *spec.opts;
  const double T = 1.0 / static_cast<double>(o.tick_hz);
  const double span_hz = o.ranges.f_max_hz - o.ranges.f_min_hz;
  std::vector<ExportNote> out;
  for (const haptics::HapticNote& hn : t.notes) {
    const synth::Note& n = hn.note;
    const std::uint64_t note_end = n.start_tick + n.duration_ticks;
    if (note_end <= spec.first_tick || n.start_tick >= spec.end_tick) continue;
    const float peak = static_cast<float>(n.amp_q16) / 65535.0f;
    const std::uint64_t a = std::max(n.start_tick, spec.first_tick);
    const std::uint64_t b = std::min(note_end, spec.end_tick);  // exclusive
    ExportNote e;
    e.start_s = static_cast<double>(a - spec.first_tick) * T;
    e.duration_s = static_cast<double>(b - a) * T;
    e.intensity = std::clamp(static_cast<double>(peak), 0.0, 1.0);
    e.sharpness = span_hz > 0 ? std::clamp((hn.freq_hz - o.ranges.f_min_hz) / span_hz, 0.0, 1.0) : 0.5;
    out.push_back(std::move(e));
  }
  return out;
}

bool is_haptic_export(const std::string& path) {
  const std::string ext = output::extension_of(path);
  return ext == "ahap" || ext == "haptic";
}

void write_haptic_export(const std::string& path, bool force, const ExportSpec& spec) {
  const std::string ext = output::extension_of(path);
  nlohmann::json j;
  if (ext == "ahap") {
    j = ahap_json(spec);
  } else if (ext == "haptic") {
    j = meta_haptic_json(spec);
  } else {
    throw BadInput("--out " + path + ": not an .ahap or .haptic file");
  }
  const std::string text = j.dump(1) + "\n";
  output::FilePtr f = output::open_for_writing(path, force);
  if (std::fwrite(text.data(), 1, text.size(), f.get()) != text.size()) throw BadInput("--out " + path + ": write failed");
}

}  // namespace hmp::exporting
