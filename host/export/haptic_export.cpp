// Note envelopes → breakpoints, and the choice of writer by extension (haptic_export.hpp).
#include "host/export/haptic_export.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <fmt/format.h>
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

envelope::Envelope note_envelope(const haptics::HapticTrack& t, const haptics::HapticOptions& o, const synth::Note& n) {
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
    const std::uint64_t a = std::max(n.start_tick, spec.first_tick);
    const std::uint64_t b = std::min(note_end, spec.end_tick);  // exclusive
    ExportNote e;
    e.start_s = static_cast<double>(a - spec.first_tick) * T;
    e.duration_s = static_cast<double>(b - a) * T;
    e.amplitude = std::clamp(static_cast<double>(n.amp_q16) / 65535.0, 0.0, 1.0);
    e.sharpness = span_hz > 0 ? std::clamp((hn.freq_hz - o.ranges.f_min_hz) / span_hz, 0.0, 1.0) : 0.5;
    out.push_back(std::move(e));
  }
  return out;
}

std::string song_file_name(const ExportSpec& spec) { return std::filesystem::path(spec.song).filename().string(); }

std::string export_description(const ExportSpec& spec) {
  const std::string name = song_file_name(spec);
  if (name.empty()) return spec.title;
  return spec.title.empty() ? name : name + " — " + spec.title;
}

bool is_haptic_export(const std::string& path) {
  const std::string ext = output::extension_of(path);
  return ext == "ahap" || ext == "haptic";
}

void write_haptic_export(const std::string& path, bool force, const ExportSpec& spec) {
  const std::string ext = output::extension_of(path);
  if (ext != "ahap" && ext != "haptic") throw BadInput("--out " + path + ": not an .ahap or .haptic file");
  if (export_notes(spec).empty()) {
    // Nothing would play: an .ahap with an empty Pattern, a .haptic of silence. Say so instead.
    const double hz = static_cast<double>(spec.opts->tick_hz);
    throw BadInput(fmt::format("--from/--to: no note of the track sounds in {:.3f}–{:.3f} s; nothing written to {}",
                               static_cast<double>(spec.first_tick) / hz, static_cast<double>(spec.end_tick) / hz,
                               path));
  }
  nlohmann::json j;
  if (ext == "ahap") {
    j = ahap_json(spec);
  } else {
    j = meta_haptic_json(spec);
  }
  const std::string text = j.dump(1) + "\n";
  output::FilePtr f = output::open_for_writing(path, force);
  if (std::fwrite(text.data(), 1, text.size(), f.get()) != text.size())
    throw BadInput("--out " + path + ": write failed");
  output::close_output(f);
}

}  // namespace hmp::exporting
