#include "host/haptics/haptic_track.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "host/common/error.hpp"
#include "host/haptics/sustain_pedal.hpp"
#include "host/midi/gm.hpp"
#include "shared/common/text.hpp"
#include "shared/envelope/gm_auto.hpp"
#include "shared/synth/frequency.hpp"

namespace hmp::haptics {

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool is_auto(const std::string& e) { return e == "auto" || e == "analogue" || e == "analog"; }

// Resolves preset names to slots: built-ins keep their fixed slot unless the user overrode them;
// user presets get slots from kFirstUserSlot on, in order of first use.
class SlotTable {
 public:
  explicit SlotTable(const HapticOptions& opts) : opts_(opts) {}

  std::uint8_t slot(const std::string& name, HapticTrack& out) {
    if (auto it = used_.find(name); it != used_.end()) return it->second;
    std::uint8_t slot = 0;
    envelope::Preset builtin;
    if (auto user = opts_.user_presets.find(name); user != opts_.user_presets.end()) {
      if (next_user_ >= envelope::kSlotCount) throw BadInput("more than 16 user presets in one track");
      slot = next_user_++;
      out.uploads.push_back({slot, user->second});
    } else if (envelope::find_builtin(name.c_str(), builtin)) {
      slot = static_cast<std::uint8_t>(builtin);
    } else {
      throw BadInput("unknown envelope preset '" + name + "'");
    }
    if (out.slot_names.size() <= slot) out.slot_names.resize(slot + 1u);
    out.slot_names[slot] = name;
    used_[name] = slot;
    return slot;
  }

 private:
  const HapticOptions& opts_;
  std::map<std::string, std::uint8_t> used_;
  std::uint8_t next_user_ = envelope::kFirstUserSlot;
};

// --amp-range-db: MAX is full scale and only the span counts.
constexpr double kMaxAmpSpanDb = 96;  // 20·log10(2^16): the device's amplitude steps
constexpr double kMaxLevelDb = 1000;  // beyond, a level's last digits are lost under the span

}  // namespace

const char* name(KeyScope s) { return s == KeyScope::song ? "song" : "track"; }

bool find_key_scope(const std::string& wanted, KeyScope& out) {
  for (KeyScope s : {KeyScope::song, KeyScope::track}) {
    if (text::iequals(wanted.c_str(), name(s))) {
      out = s;
      return true;
    }
  }
  return false;
}

KeyScope key_scope_of(const HapticOptions& opts) {
  if (opts.key_scope) return *opts.key_scope;
  return opts.mapping == mapping::Mode::legacy2013 ? KeyScope::track : KeyScope::song;
}

mapping::KeySet pitched_keys(const midi::Song& song, std::optional<std::uint32_t> track) {
  mapping::KeySet keys;
  for (const midi::Note& n : song.notes) {
    if (track && n.track != *track) continue;
    if (!midi::auto_constant_frequency(n.channel)) keys.add(n.key);
  }
  return keys;
}

mapping::Haptic drum_haptic(const mapping::Ranges& r) {
  return {(r.f_min_hz + r.f_max_hz) / 2, mapping::db_to_linear((r.a_min_db + r.a_max_db) / 2, r.a_max_db)};
}

void apply_config(const config::Config& cfg, HapticOptions& opts) {
  if (cfg.mapping_mode && !mapping::find_mode(cfg.mapping_mode->c_str(), opts.mapping)) {
    throw BadInput("config: unknown mapping mode '" + *cfg.mapping_mode + "'");
  }
  if (cfg.key_scope) {
    KeyScope scope;
    if (!find_key_scope(*cfg.key_scope, scope)) {
      throw BadInput("config: unknown key scope '" + *cfg.key_scope + "' (song, track)");
    }
    opts.key_scope = scope;
  }
  if (cfg.freq_range) {
    opts.ranges.f_min_hz = (*cfg.freq_range)[0];
    opts.ranges.f_max_hz = (*cfg.freq_range)[1];
  }
  if (cfg.amp_range_db) {
    opts.ranges.a_min_db = (*cfg.amp_range_db)[0];
    opts.ranges.a_max_db = (*cfg.amp_range_db)[1];
  }
  if (cfg.envelope) opts.envelope = lower(*cfg.envelope);
  if (cfg.end_fade_ms) opts.end_fade_ms = *cfg.end_fade_ms;
  if (cfg.polyphony && !synth::find_polyphony(cfg.polyphony->c_str(), opts.polyphony)) {
    throw BadInput("config: unknown polyphony policy '" + *cfg.polyphony + "'");
  }
  if (cfg.tick_hz) opts.tick_hz = *cfg.tick_hz;
  for (const auto& [name, adsr] : cfg.presets) {
    // A preset by a mode's name could never be chosen: --envelope NAME means the mode.
    if (is_auto(name) || name == "measured")
      throw BadInput("presets." + name + ": '" + name + "' is an envelope mode (--envelope " + name +
                     "), not a name a preset can have");
    opts.user_presets[name] = adsr;
  }
  for (const auto& [program, name] : cfg.gm) opts.gm_presets[program] = lower(name);
  for (const auto& [program, name] : cfg.measured) opts.measured_presets[program] = lower(name);
}

void validate(const HapticOptions& o, const ValueNames& names) {
  const auto& r = o.ranges;
  if (!(r.f_min_hz > 0) || !(r.f_max_hz >= r.f_min_hz) || !std::isfinite(r.f_max_hz)) {
    throw BadInput(fmt::format("{}: need 0 < min ≤ max (got {:g}:{:g})", names.freq_range, r.f_min_hz, r.f_max_hz));
  }
  const double alias = kHighestFreqFraction * o.tick_hz;
  if (r.f_max_hz >= alias) {
    throw BadInput(fmt::format("{}: top {:g} Hz must be below {:g} × tick rate = {:g} Hz (aliasing)", names.freq_range,
                               r.f_max_hz, kHighestFreqFraction, alias));
  }
  if (r.f_max_hz > synth::kFreqMaxHz) throw BadInput(names.freq_range + ": above the device's top frequency 4096 Hz");
  if (!std::isfinite(r.a_min_db) || !std::isfinite(r.a_max_db) || r.a_min_db > r.a_max_db) {
    throw BadInput(names.amp_range_db + ": need finite min ≤ max");
  }
  // MAX is full scale and only the span counts; one wider than the device's 16-bit amplitude (96 dB)
  // puts the quietest notes below its smallest step: silent.
  if (std::fabs(r.a_min_db) > kMaxLevelDb || std::fabs(r.a_max_db) > kMaxLevelDb ||
      r.a_max_db - r.a_min_db > kMaxAmpSpanDb) {
    throw BadInput(
        fmt::format("{} {:g}:{:g}: need levels within ±{:g} dB at most {:g} dB apart (the "
                    "device's 16-bit amplitude)",
                    names.amp_range_db, r.a_min_db, r.a_max_db, kMaxLevelDb, kMaxAmpSpanDb));
  }
  if (!(o.end_fade_ms >= 0 && o.end_fade_ms <= 1000)) throw BadInput(names.end_fade_ms + ": must be in [0, 1000]");
  if (!(o.speed >= 0.5 && o.speed <= 2.0))
    throw BadInput(fmt::format("--speed: must be in [0.5, 2] (got {:g})", o.speed));
  for (const auto* table : {&o.gm_presets, &o.measured_presets}) {
    for (const auto& [program, name] : *table) {
      envelope::Preset p;
      if (!o.user_presets.count(name) && !envelope::find_builtin(name.c_str(), p)) {
        const std::string entry = fmt::format("{}.{}", table == &o.gm_presets ? "gm" : "measured", program);
        const auto file = names.table_entry_file.find(entry);
        throw BadInput(fmt::format("{}: {} names unknown preset '{}'",
                                   file != names.table_entry_file.end() ? file->second : "config", entry, name));
      }
    }
  }
  if (o.envelope == "measured" && o.measured_presets.empty()) {
    throw BadInput(names.envelope +
                   " measured: no measured presets configured (write them with "
                   "`hmp envelope measure --all --out FILE.toml`, then give --config FILE.toml)");
  }
  if (!is_auto(o.envelope) && o.envelope != "measured") {
    envelope::Preset p;
    if (!o.user_presets.count(o.envelope) && !envelope::find_builtin(o.envelope.c_str(), p)) {
      std::string known = "auto, analogue, measured";
      for (std::uint8_t i = 0; i < envelope::kBuiltinCount; ++i) {
        known += std::string(", ") + envelope::name(static_cast<envelope::Preset>(i));
      }
      for (const auto& [name, adsr] : o.user_presets) known += ", " + name;
      throw BadInput(names.envelope + ": unknown preset '" + o.envelope + "' (known: " + known + ")");
    }
  }
}

std::uint64_t seconds_to_tick(std::int64_t micros, std::uint32_t tick_hz) {
  if (micros <= 0) return 0;
  // round(µs · hz / 1e6), halves up, exactly: floor((2 · µs · hz + 1e6) / 2e6).
  const auto num = static_cast<unsigned __int128>(micros) * tick_hz * 2u + 1000000u;
  return static_cast<std::uint64_t>(num / 2000000u);
}

// The `auto` table (shared/envelope cannot see host/midi) and the song model agree on the drum channel.
static_assert(envelope::kGmDrumChannel == midi::kDrumChannel);

std::string auto_preset_name(const HapticOptions& opts, std::uint8_t program, std::uint8_t channel) {
  if (channel != midi::kDrumChannel) {
    if (auto it = opts.gm_presets.find(program); it != opts.gm_presets.end()) return it->second;
    if (!envelope::table1_instrument(program)) {
      if (auto it = opts.measured_presets.find(program); it != opts.measured_presets.end()) return it->second;
    }
  }
  return envelope::name(envelope::auto_preset(program, channel));
}

std::string measured_preset_name(const HapticOptions& opts, std::uint8_t program, std::uint8_t channel) {
  if (channel == midi::kDrumChannel) return auto_preset_name(opts, program, channel);
  if (auto it = opts.measured_presets.find(program); it != opts.measured_presets.end()) return it->second;
  throw BadInput(
      fmt::format("--envelope measured: no measured preset for program {} ({}) in the config "
                  "(hmp envelope measure --program {} --out FILE.toml)",
                  program, midi::gm_program_name(program), program));
}

std::string note_preset_name(const HapticOptions& opts, std::uint8_t program, std::uint8_t channel) {
  if (is_auto(opts.envelope)) {
    return opts.mapping == mapping::Mode::legacy2013 ? "legacy2013" : auto_preset_name(opts, program, channel);
  }
  if (opts.envelope == "measured") return measured_preset_name(opts, program, channel);
  return opts.envelope;
}

std::vector<synth::Note> HapticTrack::device_notes() const {
  std::vector<synth::Note> out;
  out.reserve(notes.size());
  for (const HapticNote& n : notes) out.push_back(n.note);
  return out;
}

HapticTrack build_haptic_track(const midi::Song& song, std::uint32_t track, const HapticOptions& opts) {
  validate(opts);
  if (track >= song.tracks.size()) throw BadInput("--track " + std::to_string(track) + ": no such track");
  const std::vector<midi::Note> notes = song.track_notes(track);

  HapticTrack out;
  out.track = track;
  // Drum notes are felt at a constant frequency (design §6), so only pitched notes define the key range.
  out.key_scope = key_scope_of(opts);
  out.keys = pitched_keys(song, out.key_scope == KeyScope::track ? std::optional<std::uint32_t>(track) : std::nullopt);
  const mapping::Mapper mapper(opts.mapping, opts.ranges, out.keys);
  out.jnd_steps = mapper.jnd_steps(pitched_keys(song, track));
  const mapping::Haptic drum = drum_haptic(opts.ranges);
  SlotTable slots(opts);

  out.notes.reserve(notes.size());
  out.speed = opts.speed;
  const auto play_us = [&](std::int64_t us) {
    return opts.speed == 1.0 ? us : std::llround(static_cast<double>(us) / opts.speed);
  };
  const std::vector<std::uint64_t> pedal_ends =
      opts.pedal ? pedal_end_ticks(song, notes) : std::vector<std::uint64_t>{};
  for (std::size_t i = 0; i < notes.size(); ++i) {
    const midi::Note& n = notes[i];
    HapticNote h;
    h.key = n.key;
    h.channel = n.channel;
    h.program = n.program;
    const std::int64_t start_us = song.start_us(n);
    const std::int64_t end_us = opts.pedal ? song.tempo_map.micros(pedal_ends[i]) : song.end_us(n);
    h.start_s = static_cast<double>(start_us) * 1e-6;
    h.end_s = static_cast<double>(end_us) * 1e-6;
    const mapping::Haptic m = midi::auto_constant_frequency(n.channel) ? drum : mapper.map(n.key);
    h.freq_hz = m.freq_hz;
    h.amplitude = m.amplitude;

    const std::string preset = note_preset_name(opts, n.program, n.channel);

    const std::uint64_t start = seconds_to_tick(play_us(start_us), opts.tick_hz);
    const std::uint64_t end = seconds_to_tick(play_us(end_us), opts.tick_hz);
    h.note.start_tick = start;
    h.note.duration_ticks =
        static_cast<std::uint32_t>(std::clamp<std::uint64_t>(end > start ? end - start : 1, 1, UINT32_MAX));
    h.note.freq_q20 = synth::freq_to_q20(m.freq_hz);
    h.note.amp_q16 = synth::amp_to_q16(m.amplitude);
    h.note.preset = slots.slot(preset, out);
    h.note.track = static_cast<std::uint8_t>(std::min<std::uint32_t>(track, 255));
    out.notes.push_back(h);
  }
  std::stable_sort(out.notes.begin(), out.notes.end(),
                   [](const HapticNote& a, const HapticNote& b) { return a.note.start_tick < b.note.start_tick; });
  return out;
}

RenderSettings render_settings(const HapticOptions& opts) {
  RenderSettings settings;
  settings.synth.tick_hz = opts.tick_hz;
  settings.synth.end_fade_ms = static_cast<float>(opts.end_fade_ms);
  settings.polyphony = opts.polyphony;
  return settings;
}

}  // namespace hmp::haptics
