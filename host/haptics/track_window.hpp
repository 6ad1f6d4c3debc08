#pragma once
// A song's haptic track over a window of time: choosing the track by what the user calls it, mapping it,
// and turning --from/--to into device ticks. What `render` and `sim` start from (and `play` and `study`
// choose their track with). The messages name the command-line options they come from.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "host/common/error.hpp"
#include "host/haptics/haptic_track.hpp"
#include "host/midi/smf_reader.hpp"

namespace hmp::haptics {

// `--track T`: a 0-based index, or a case-insensitive part of a track's name or GM instrument name.
// An exact (case-insensitive) name match wins; otherwise exactly one track with notes must match.
// Unknown or ambiguous → BadInput listing the candidates.
std::uint32_t select_track(const midi::Song& song, const std::string& query);

struct TrackWindow {
  midi::ReadResult read;  // the song and the reader's warnings
  std::uint32_t track = 0;
  HapticTrack haptic;
  std::uint64_t first_tick = 0;  // --from (default: the start)
  std::uint64_t end_tick = 0;    // --to (default: the song's end or the last note's end, whichever is later)
};

// Where the reader's warnings go, one line each (the command prints them as "warning: …").
using WarningSink = std::function<void(const std::string&)>;

// The error of a song refused after its reading gave warnings: the error, and how many there were.
std::string with_reading_warnings(const std::string& error, std::size_t warnings);

// Runs a command's `checks` of a song just read; the reader's warnings go to `warn` once they pass. A song
// they refuse gets its one error line, which counts the warnings instead of printing them before it.
template <class Checks>
void check_song_then_warn(const midi::ReadResult& read, const WarningSink& warn, Checks&& checks) {
  try {
    checks();
  } catch (const BadInput& e) {
    if (read.warnings.empty()) throw;
    throw BadInput(with_reading_warnings(e.what(), read.warnings.size()));
  }
  for (const midi::Warning& w : read.warnings) warn(w.message);
}

// Loads the song (its warnings to `warn` once the rest has passed), selects the track, maps it, and converts
// --from/--to (seconds ≥ 0) to ticks. Throws BadInput on a bad window or an empty one.
TrackWindow load_track_window(const std::string& song, const std::string& track, const HapticOptions& opts,
                              std::optional<double> from_s, std::optional<double> to_s, const WarningSink& warn);

}  // namespace hmp::haptics
