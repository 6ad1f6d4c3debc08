#pragma once
// From a song's track to the notes the device plays: mapping (design §5), envelope choice (design §6 `auto`,
// a fixed preset, or a user preset from the config), and note times → device ticks (design §6 "Ticks").
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "host/config/config.hpp"
#include "host/haptics/signal_renderer.hpp"
#include "host/midi/song.hpp"
#include "shared/mapping/mapping.hpp"
#include "shared/synth/engine.hpp"
#include "shared/synth/voice.hpp"
#include "shared/synth/tick_rate.hpp"

namespace hmp::haptics {

// Which notes define k_min, k_max and k_ε: every pitched note of the song (the 2015 paper, §5.4: "in the
// song", so bass instruments are felt low and treble ones high) or the haptic track's only (the 2013
// paper: "in the track", so every instrument spans the whole frequency range).
enum class KeyScope : std::uint8_t { song, track };
const char* name(KeyScope s);
bool find_key_scope(const std::string& name, KeyScope& out);  // case-insensitive

// Everything the mapping/envelope options of design §3 choose.
struct HapticOptions {
  mapping::Mode mapping = mapping::Mode::paper;
  mapping::Ranges ranges{};
  // Unset: the mapping's own reading (paper, rank, constant: song; legacy2013: track).
  std::optional<KeyScope> key_scope;
  // auto | analogue (= auto) | measured | square | triangle | any preset name
  std::string envelope = "auto";
  synth::Polyphony polyphony = synth::Polyphony::sum;
  double end_fade_ms = 2.0;
  std::uint32_t tick_hz = synth::kNominalTickHz;
  // Playback speed (`hmp play`'s [ and ]): the device's ticks are play time = song time / speed, so a
  // note lasts 1/speed as long on the device; the notes' start_s/end_s stay song time.
  double speed = 1.0;
  bool pedal = false;  // --pedal: notes released under the sustain pedal last until it lifts (sustain_pedal.hpp)
  std::map<std::string, envelope::Adsr> user_presets;    // from the config
  std::map<std::uint8_t, std::string> gm_presets;        // program → preset name, from the config
  std::map<std::uint8_t, std::string> measured_presets;  // program → preset fitted to its sound (config)
};

// Applies a loaded config (values the command line did not set explicitly are taken from it; the caller
// applies the config first and the command line after).
void apply_config(const config::Config& cfg, HapticOptions& opts);
// The highest vibration frequency, as a fraction of the tick rate: the device's sine is one sample a
// tick, and above this its alias is as loud as it.
inline constexpr double kHighestFreqFraction = 0.45;

// How validate()'s messages name the values they are about: by default the command-line options; a value
// a config set is named by its file and key there ("a.toml: mapping.freq_range"), and a program table's
// entry by its file ("a.toml: gm.73"; "config: gm.73" where none is known).
struct ValueNames {
  std::string freq_range = "--freq-range", amp_range_db = "--amp-range-db", end_fade_ms = "--end-fade-ms",
              envelope = "--envelope";
  std::map<std::string, std::string> table_entry_file;  // "gm.73" → its config file
};

// Throws BadInput when the options cannot work: empty/inverted ranges, f_max ≥ kHighestFreqFraction ×
// tick rate, unknown envelope name.
void validate(const HapticOptions& opts, const ValueNames& names = {});

// One note on its way to the device, with where it came from.
struct HapticNote {
  synth::Note note;  // ticks, Q12.20 frequency, Q16 amplitude, preset slot
  std::uint8_t key = 0;
  std::uint8_t channel = 0;
  std::uint8_t program = 0;  // the GM program it plays with (its sound's onset, audio_player.hpp)
  double freq_hz = 0;        // mapped, before quantisation
  double amplitude = 0;      // mapped, linear
  double start_s = 0, end_s = 0;
};

struct HapticTrack {
  std::uint32_t track = 0;
  std::vector<HapticNote> notes;        // sorted by start tick
  std::vector<UserPreset> uploads;      // user presets the notes use, with their slots
  std::vector<std::string> slot_names;  // preset name of every slot used (index = slot), "" if unused
  mapping::KeySet keys;                 // the keys that set the mapping's range (key_scope's)
  KeyScope key_scope = KeyScope::song;
  double jnd_steps = 0;  // of the range the track's own keys span
  double speed = 1.0;    // the options' speed: the notes' ticks are song time / speed

  std::vector<synth::Note> device_notes() const;
};

// design §6 ticks: start = round(start_s/T) with halves up; N = max(1, round(end_s/T) − start).
std::uint64_t seconds_to_tick(std::int64_t micros, std::uint32_t tick_hz);

// The key scope in force: the option when set, else the mapping's own.
KeyScope key_scope_of(const HapticOptions& opts);
// The keys of the song's pitched notes (GM channel 10's keys choose drums, not pitches: left out), or of
// one track's with `track`.
mapping::KeySet pitched_keys(const midi::Song& song, std::optional<std::uint32_t> track = std::nullopt);

// What a drum note (GM channel 10) is felt as: the middle of the frequency and amplitude ranges.
mapping::Haptic drum_haptic(const mapping::Ranges& ranges);

// The preset name `auto` picks for one note: the config's [gm] table first; then, for an instrument Table 1
// lacks, its measured preset when the config has one; then design §6.
// `measured` picks the measured preset (drums: what `auto` picks); BadInput when the program has none.
std::string auto_preset_name(const HapticOptions& opts, std::uint8_t program, std::uint8_t channel);
std::string measured_preset_name(const HapticOptions& opts, std::uint8_t program, std::uint8_t channel);
// The preset a note of (program, channel) plays with under opts.envelope: auto's, measured's, or the one named.
std::string note_preset_name(const HapticOptions& opts, std::uint8_t program, std::uint8_t channel);

HapticTrack build_haptic_track(const midi::Song& song, std::uint32_t track, const HapticOptions& opts);

// The shared engine's settings the options ask for (tick rate, end fade, polyphony): what every renderer
// of a track's signal (render, the view's strip, the video's haptic audio) uses.
RenderSettings render_settings(const HapticOptions& opts);

}  // namespace hmp::haptics
