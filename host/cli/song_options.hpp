#pragma once
// Command-line pieces shared by the song subcommands (info, render, play): loading the song, choosing
// the haptic track (--track), and the mapping/envelope options of design §3.
#include <cstdint>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "host/haptics/haptic_track.hpp"
#include "host/midi/smf_reader.hpp"

namespace hmp::cli {

// `--track T`: a 0-based index, or a case-insensitive part of a track's name or GM instrument name.
// An exact (case-insensitive) name match wins; otherwise exactly one track with notes must match.
// Unknown or ambiguous → BadInput listing the candidates.
std::uint32_t select_track(const midi::Song& song, const std::string& query);

// What the user typed; unset optionals fall back to the config file, then to the defaults.
struct HapticCliOptions {
  std::optional<std::string> mapping, freq_range, amp_range_db, envelope, polyphony;
  std::optional<double> end_fade_ms;
  std::optional<std::uint32_t> tick_hz;
  std::optional<std::string> config_path;
};

void add_haptic_options(CLI::App* cmd, HapticCliOptions& o);
haptics::HapticOptions resolve(const HapticCliOptions& o);

// A song's haptic track over a window of device ticks: what `render` and `sim` both start from.
struct TrackWindow {
  midi::ReadResult read;            // the song and the reader's warnings (already printed)
  std::uint32_t track = 0;
  haptics::HapticTrack haptic;
  std::uint64_t first_tick = 0;     // --from (default: the start)
  std::uint64_t end_tick = 0;       // --to (default: the song's end or the last note's end, whichever is later)
};
// Loads the song (warnings to stderr), selects the track, maps it, and converts --from/--to (seconds ≥ 0)
// to ticks. Throws BadInput on a bad window or an empty one.
TrackWindow load_track_window(const std::string& song, const std::string& track, const haptics::HapticOptions& opts,
                              std::optional<double> from_s, std::optional<double> to_s);

// "A:B" → {A, B}; throws BadInput naming the option.
std::pair<double, double> parse_range(const std::string& option, const std::string& text);

}  // namespace hmp::cli
