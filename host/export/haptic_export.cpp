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

constexpr double kRefineTolerance = 0.01;  // of the note's peak

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

std::vector<ExportNote> export_notes(const ExportSpec& spec, std::uint32_t step_ticks) {
  const haptics::HapticTrack& t = *spec.track;
  const haptics::HapticOptions& o = *spec.opts;
  const double T = 1.0 / static_cast<double>(o.tick_hz);
  const double span_hz = o.ranges.f_max_hz - o.ranges.f_min_hz;
  if (step_ticks == 0) step_ticks = 1;
  std::vector<ExportNote> out;
  for (const haptics::HapticNote& hn : t.notes) {
    const synth::Note& n = hn.note;
    const std::uint64_t note_end = n.start_tick + n.duration_ticks;
    if (note_end <= spec.first_tick || n.start_tick >= spec.end_tick) continue;
    const envelope::Envelope env = note_envelope(t, o, n);
    const float peak = static_cast<float>(n.amp_q16) / 65535.0f;
    const std::uint64_t a = std::max(n.start_tick, spec.first_tick);
    const std::uint64_t b = std::min(note_end, spec.end_tick);  // exclusive
    ExportNote e;
    e.start_s = static_cast<double>(a - spec.first_tick) * T;
    e.duration_s = static_cast<double>(b - a) * T;
    e.intensity = std::clamp(static_cast<double>(peak), 0.0, 1.0);
    e.sharpness = span_hz > 0 ? std::clamp((hn.freq_hz - o.ranges.f_min_hz) / span_hz, 0.0, 1.0) : 0.5;
    const double inv_peak = peak > 0 ? 1.0 / static_cast<double>(peak) : 0.0;
    // Every tick's level, then breakpoints: the step grid plus the note's last tick, refined where linear
    // interpolation between two breakpoints misses a tick by more than kRefineTolerance (phase corners,
    // the end fade).
    std::vector<double> lv(static_cast<std::size_t>(b - a));
    for (std::uint64_t k = a; k < b; ++k)
      lv[k - a] = std::clamp(static_cast<double>(env.at(static_cast<std::uint32_t>(k - n.start_tick))) * inv_peak, 0.0, 1.0);
    std::vector<std::size_t> keep;
    for (std::size_t k = 0; k < lv.size(); k += step_ticks) keep.push_back(k);
    if (keep.back() != lv.size() - 1) keep.push_back(lv.size() - 1);
    std::vector<std::size_t> refined{keep.front()};
    const auto refine = [&](auto&& self, std::size_t i0, std::size_t i1) -> void {
      std::size_t worst = i0;
      double worst_err = kRefineTolerance;
      for (std::size_t k = i0 + 1; k < i1; ++k) {
        const double lin = lv[i0] + (lv[i1] - lv[i0]) * static_cast<double>(k - i0) / static_cast<double>(i1 - i0);
        if (std::abs(lin - lv[k]) > worst_err) {
          worst_err = std::abs(lin - lv[k]);
          worst = k;
        }
      }
      if (worst != i0) {
        self(self, i0, worst);
        self(self, worst, i1);
      } else {
        refined.push_back(i1);
      }
    };
    for (std::size_t q = 0; q + 1 < keep.size(); ++q) refine(refine, keep[q], keep[q + 1]);
    for (std::size_t k : refined) e.envelope.push_back({static_cast<double>(k) * T, lv[k]});
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
