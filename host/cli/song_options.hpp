#pragma once
// Command-line pieces shared by the song subcommands (info, render, play): loading the song, choosing
// the haptic track (--track), and the mapping/envelope options of design §3.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "host/audio/audio_options.hpp"
#include "host/audio/audio_player.hpp"
#include "host/haptics/haptic_track.hpp"
#include "host/haptics/track_window.hpp"
#include "host/midi/smf_reader.hpp"

namespace hmp::cli {

using haptics::load_track_window;
using haptics::select_track;
using haptics::TrackWindow;

// What the user typed; unset optionals fall back to the config file, then to the defaults.
struct HapticCliOptions {
  std::optional<std::string> mapping, key_scope, freq_range, amp_range_db, envelope, polyphony;
  std::optional<double> end_fade_ms;
  std::optional<std::uint32_t> tick_hz;
  std::vector<std::string> config_paths;  // --config, repeatable: later files override earlier ones
  bool pedal = false;
};

void add_haptic_options(CLI::App* cmd, HapticCliOptions& o);
haptics::HapticOptions resolve(const HapticCliOptions& o);
// --mapping's text → the mode; throws BadInput naming the text and the choices.
mapping::Mode parse_mapping_mode(const std::string& text);

// No --track: the first track with notes whose instrument has its own envelope in Table 1 (design §6:
// organ … contrabass), else the first track with notes. A song without notes is bad input.
std::uint32_t default_haptic_track(const midi::Song& song);
// Whether a track's instrument has its own envelope in Table 1 (what default_haptic_track looks for).
bool has_table1_instrument(const midi::Track& track);
// `2 "Flute" (Flute)`
std::string describe_track(const midi::Song& song, std::uint32_t index);

// CLI::Range for a real number that also refuses NaN and infinities (CLI11's lets NaN through: every
// comparison with it is false).
CLI::Validator finite_range(double least, double most);
// The SoundFont a user named: a readable file that starts like a SoundFont 2/3; BadInput naming --soundfont
// otherwise (FluidSynth would play on silently).
void check_soundfont_option(const std::string& path);

// The song's audio on the command line (play, view, study): --no-audio, --audio-driver, --soundfont,
// --audio-buffer-ms.
struct AudioCliOptions {
  bool no_audio = false;
  std::optional<std::string> driver, soundfont;
  std::optional<double> buffer_ms;
};
void add_audio_options(CLI::App* cmd, AudioCliOptions& o);
audio::AudioOptions audio_options(const AudioCliOptions& o);
// Waits up to 0.5 s for the sound's first driver callback: the output latency is the period the driver
// uses, which may not be the one asked for. A warning on stderr if none came (the latency then a guess).
void await_audio_period(const audio::AudioPlayer& audio);

// "warning: MESSAGE" on stderr: where the commands send the reader's warnings.
void warn_on_stderr(const std::string& message);

// "A:B" → {A, B}; throws BadInput naming the option.
std::pair<double, double> parse_range(const std::string& option, const std::string& text);

}  // namespace hmp::cli
