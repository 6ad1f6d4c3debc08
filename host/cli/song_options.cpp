#include "host/cli/song_options.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>

#include <fmt/format.h>

#include "host/audio/soundfont.hpp"
#include "host/common/error.hpp"
#include "host/common/input_file.hpp"
#include "host/common/number_text.hpp"
#include "host/midi/gm.hpp"
#include "host/simulate/plant_config.hpp"

namespace hmp::cli {

namespace {
std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}
}  // namespace

void warn_on_stderr(const std::string& message) { std::fprintf(stderr, "warning: %s\n", message.c_str()); }

std::pair<double, double> parse_range(const std::string& option, const std::string& text) {
  const auto colon = text.find(':');
  auto num = [&](const std::string& s) {
    const std::optional<double> v = finite_number(s);
    if (!v) throw BadInput(option + " " + text + ": expected MIN:MAX");
    return *v;
  };
  if (colon == std::string::npos) throw BadInput(option + " " + text + ": expected MIN:MAX");
  return {num(text.substr(0, colon)), num(text.substr(colon + 1))};
}

void add_haptic_options(CLI::App* cmd, HapticCliOptions& o) {
  cmd->add_option("--mapping", o.mapping, "Pitch mapping: paper (default), rank, constant, legacy2013");
  cmd->add_option("--key-scope", o.key_scope,
                  "Keys that set the range: song (paper's reading, default) or track (legacy2013's default)");
  cmd->add_option("--freq-range", o.freq_range, "Haptic frequency range MIN:MAX in Hz (default 50:250)");
  cmd->add_option("--amp-range-db", o.amp_range_db,
                  "Amplitude range MIN:MAX in dB, MAX = full scale, at most 96 dB apart (default 7.5:30)");
  cmd->add_option("--envelope", o.envelope,
                  "auto (the instrument's own, = analogue), measured (fitted to the SoundFont by hmp envelope "
                  "measure), square, triangle, or any preset name");
  cmd->add_option("--polyphony", o.polyphony, "Overlapping notes: sum (default), highest, latest");
  cmd->add_option("--end-fade-ms", o.end_fade_ms, "Fade at each note's end in ms (default 2, 0 = paper-exact)");
  cmd->add_flag("--pedal", o.pedal, "A note released under the sustain pedal (CC64) lasts until the pedal lifts");
  cmd->add_option("--tick-hz", o.tick_hz, "Device tick rate in Hz (default 1000)")->check(CLI::Range(100u, 100000u));
  // No CLI::ExistingFile here: config::load refuses a missing file or a directory with the message every
  // file the user names gets (host/common/input_file.hpp).
  cmd->add_option("--config", o.config_paths,
                  "TOML file: user presets, GM table, ranges, device settings (repeatable: later ones win)")
      ->allow_extra_args(false)  // one file per --config: a SONG after it stays the SONG
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

mapping::Mode parse_mapping_mode(const std::string& text) {
  mapping::Mode mode;
  if (!mapping::find_mode(text.c_str(), mode))
    throw BadInput("--mapping " + text + ": unknown (paper, rank, constant, legacy2013)");
  return mode;
}

haptics::HapticOptions resolve(const HapticCliOptions& o) {
  haptics::HapticOptions h;
  // A value a config set last is named in validate()'s messages by its file and key; one the command line
  // set, by its option (ValueNames' defaults).
  const haptics::ValueNames by_option;
  haptics::ValueNames names;
  for (const std::string& path : o.config_paths) {
    const config::Config c = config::load(path);
    if (c.freq_range) names.freq_range = path + ": mapping.freq_range";
    if (c.amp_range_db) names.amp_range_db = path + ": mapping.amp_range_db";
    if (c.envelope) names.envelope = path + ": envelope.default";
    if (c.end_fade_ms) names.end_fade_ms = path + ": envelope.end_fade_ms";
    for (const auto& [table, entries] : {std::pair{"gm.", &c.gm}, std::pair{"measured.", &c.measured}}) {
      for (const auto& [program, name] : *entries) names.table_entry_file[table + std::to_string(program)] = path;
    }
    try {
      haptics::apply_config(c, h);
      // [plant] is hmp sim's and calibrate's; a value they would refuse is refused by every command, so
      // that one config is good or bad everywhere.
      sim::plant::PlantParams unused;
      simulate::apply_plant_settings(c.plant, {}, unused);
    } catch (const BadInput& e) {
      std::string what = e.what();  // which of several configs, in place of a bare "config: "
      if (what.starts_with("config: ")) what.erase(0, 8);
      throw BadInput(path + ": " + what);
    }
  }
  if (o.mapping) h.mapping = parse_mapping_mode(*o.mapping);
  if (o.key_scope) {
    haptics::KeyScope scope;
    if (!haptics::find_key_scope(*o.key_scope, scope))
      throw BadInput("--key-scope " + *o.key_scope + ": unknown (song, track)");
    h.key_scope = scope;
  }
  if (o.mapping && h.mapping == mapping::Mode::legacy2013 && !o.freq_range) {
    h.ranges.f_min_hz = mapping::kLegacyFminHz;
    h.ranges.f_max_hz = mapping::kLegacyFmaxHz;
  }
  if (o.freq_range) {
    std::tie(h.ranges.f_min_hz, h.ranges.f_max_hz) = parse_range("--freq-range", *o.freq_range);
    names.freq_range = by_option.freq_range;
  }
  if (o.amp_range_db) {
    std::tie(h.ranges.a_min_db, h.ranges.a_max_db) = parse_range("--amp-range-db", *o.amp_range_db);
    names.amp_range_db = by_option.amp_range_db;
  }
  if (o.envelope) {
    h.envelope = lower(*o.envelope);
    names.envelope = by_option.envelope;
  }
  if (o.polyphony && !synth::find_polyphony(o.polyphony->c_str(), h.polyphony)) {
    throw BadInput("--polyphony " + *o.polyphony + ": unknown (sum, highest, latest)");
  }
  if (o.end_fade_ms) {
    h.end_fade_ms = *o.end_fade_ms;
    names.end_fade_ms = by_option.end_fade_ms;
  }
  h.pedal = o.pedal;
  if (o.tick_hz) h.tick_hz = *o.tick_hz;
  haptics::validate(h, names);
  return h;
}

std::string describe_track(const midi::Song& song, std::uint32_t index) {
  const midi::Track& t = song.tracks[index];
  return fmt::format("{} \"{}\" ({})", t.index, t.name, midi::gm_instrument_name(t.program(), t.channel()));
}

bool has_table1_instrument(const midi::Track& track) {
  const auto preset = static_cast<std::uint8_t>(midi::auto_preset(track.program(), track.channel()));
  return preset <= static_cast<std::uint8_t>(envelope::Preset::contrabass);
}

std::uint32_t default_haptic_track(const midi::Song& song) {
  std::optional<std::uint32_t> first;
  for (const midi::Track& t : song.tracks) {
    if (t.note_count == 0) continue;
    if (!first) first = t.index;
    if (has_table1_instrument(t)) return t.index;
  }
  if (!first) throw BadInput("the song has no notes to play");
  return *first;
}

void add_audio_options(CLI::App* cmd, AudioCliOptions& o) {
  CLI::Option* no_audio = cmd->add_flag("--no-audio", o.no_audio, "No sound: no audio device is opened");
  // FluidSynth's drivers that take a callback (its `file` driver does not); `virtual` is the simulated
  // sound card the skew benchmark measures with: it plays to nowhere, in real time.
  cmd->add_option("--audio-driver", o.driver,
                  "Audio output: pulseaudio, alsa, sdl2, jack, oss, pipewire or virtual (default: the first of "
                  "pulseaudio, alsa, sdl2 that opens)")
      ->check(CLI::IsMember({"pulseaudio", "alsa", "sdl2", "jack", "oss", "pipewire", "virtual"}))
      ->excludes(no_audio);
  cmd->add_option("--soundfont", o.soundfont,
                  "SoundFont (.sf2/.sf3) for the song's audio (default: the GM one installed)");
  // A busy machine can hold even a real-time audio thread off its core for tens of milliseconds; a
  // longer buffer rides that out. Sound and vibration stay together either way (the latency is
  // compensated); a longer buffer only makes pause and seek answer later.
  cmd->add_option("--audio-buffer-ms", o.buffer_ms,
                  "Audio output buffer in ms, rounded to whole 256-frame periods (default 21); raise it if "
                  "the sound drops out on a busy machine")
      ->check(finite_range(10.0, 1000.0))
      ->excludes(no_audio);
}

CLI::Validator finite_range(double least, double most) {
  return CLI::Validator(
      [least, most](std::string& text) {
        const std::optional<double> v = finite_number(text);
        if (v && *v >= least && *v <= most) return std::string();
        return fmt::format("{} is not a number from {:g} to {:g}", text, least, most);
      },
      fmt::format("FLOAT in [{:g} - {:g}]", least, most));
}

void check_soundfont_option(const std::string& path) {
  check_input_file(path);
  if (const std::string why = audio::soundfont_format_problem(path); !why.empty())
    throw BadInput("--soundfont " + path + ": " + why);
}

audio::AudioOptions audio_options(const AudioCliOptions& o) {
  audio::AudioOptions a;
  a.enabled = !o.no_audio;
  if (o.driver) a.drivers = {*o.driver};
  if (o.buffer_ms) {
    const double period_ms = 1e3 * a.period_frames / a.synth.sample_rate;
    a.periods = std::max(2, static_cast<int>(std::lround(*o.buffer_ms / period_ms)));
  }
  if (o.soundfont) {
    check_soundfont_option(*o.soundfont);  // a bad --soundfont is an error, not a silent song
    a.soundfont = *o.soundfont;
  }
  return a;
}

void await_audio_period(const audio::AudioPlayer& audio) {
  if (audio.audible() && !audio.wait_for_first_callback(std::chrono::milliseconds(500)))
    std::fprintf(stderr, "warning: audio: the %s driver has not called back in 0.5 s; its latency is a guess\n",
                 audio.driver_name().c_str());
}

}  // namespace hmp::cli
