#include "host/haptics/track_window.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "host/common/error.hpp"
#include "host/common/song_window.hpp"
#include "host/midi/gm.hpp"

namespace hmp::haptics {

namespace {
std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string describe(const midi::Track& t) {
  return std::to_string(t.index) + " \"" + t.name + "\" (" + midi::gm_instrument_name(t.program(), t.channel()) + ")";
}

// The track, its mapping and the window of a song read into `w`.
void choose_window(TrackWindow& w, const std::string& track, const HapticOptions& opts, std::optional<double> from_s,
                   std::optional<double> to_s) {
  w.track = select_track(w.read.song, track);
  w.haptic = build_haptic_track(w.read.song, w.track, opts);
  std::uint64_t song_end = seconds_to_tick(w.read.song.duration_us, opts.tick_hz);
  for (const HapticNote& n : w.haptic.notes) {
    song_end = std::max(song_end, n.note.start_tick + n.note.duration_ticks);
  }
  if (song_end == 0) throw BadInput("the song lasts 0 s (no notes, no events after its start)");
  // The song's end in µs, rounded up, so that the window's end comes back to song_end in ticks.
  const auto song_end_us = static_cast<std::int64_t>(
      (static_cast<unsigned __int128>(song_end) * 1000000u + opts.tick_hz - 1) / opts.tick_hz);
  const SongWindowUs window = song_window(from_s, to_s, song_end_us);
  w.first_tick = seconds_to_tick(window.begin_us, opts.tick_hz);
  w.end_tick = std::min(seconds_to_tick(window.end_us, opts.tick_hz), song_end);
  if (w.end_tick <= w.first_tick) throw BadInput("--from/--to: empty window (shorter than a tick)");
}
}  // namespace

std::string with_reading_warnings(const std::string& error, std::size_t warnings) {
  return error + "; reading the file gave " + std::to_string(warnings) + " warning" + (warnings == 1 ? "" : "s") +
         " (hmp info lists them)";
}

std::uint32_t select_track(const midi::Song& song, const std::string& query) {
  if (song.tracks.empty()) throw BadInput("the song has no tracks");
  char* end = nullptr;
  const long index = std::strtol(query.c_str(), &end, 10);
  if (!query.empty() && *end == '\0') {
    if (index < 0 || static_cast<std::size_t>(index) >= song.tracks.size()) {
      throw BadInput("--track " + query + ": no such track (0–" + std::to_string(song.tracks.size() - 1) + ")");
    }
    return static_cast<std::uint32_t>(index);
  }
  const std::string q = lower(query);
  std::vector<const midi::Track*> matches;
  for (const midi::Track& t : song.tracks) {
    const std::string name = lower(t.name);
    const std::string instrument = lower(midi::gm_instrument_name(t.program(), t.channel()));
    if (t.note_count > 0 && (name == q || instrument == q) && matches.empty()) {
      // An exact match is unambiguous even when other names contain the text.
      bool unique_exact = true;
      for (const midi::Track& o : song.tracks) {
        if (&o != &t && o.note_count > 0 && lower(o.name) == q) unique_exact = false;
      }
      if (unique_exact && name == q) return t.index;
    }
    if (t.note_count > 0 && (name.find(q) != std::string::npos || instrument.find(q) != std::string::npos)) {
      matches.push_back(&t);
    }
  }
  if (matches.size() == 1) return matches.front()->index;
  std::string list;
  for (const midi::Track* t : matches.empty() ? std::vector<const midi::Track*>{} : matches)
    list += "; " + describe(*t);
  if (matches.empty()) {
    for (const midi::Track& t : song.tracks) {
      if (t.note_count > 0) list += "; " + describe(t);
    }
    throw BadInput("--track '" + query + "': no track matches (" +
                   (list.empty() ? std::string("the song has no notes") : "tracks with notes: " + list.substr(2)) +
                   ")");
  }
  throw BadInput("--track '" + query + "' is ambiguous (candidates: " + list.substr(2) + ")");
}

TrackWindow load_track_window(const std::string& song, const std::string& track, const HapticOptions& opts,
                              std::optional<double> from_s, std::optional<double> to_s, const WarningSink& warn) {
  check_window_times(from_s, to_s);  // before the song is read
  TrackWindow w;
  w.read = midi::load_song(song);
  check_song_then_warn(w.read, warn, [&] { choose_window(w, track, opts, from_s, to_s); });
  return w;
}

}  // namespace hmp::haptics
