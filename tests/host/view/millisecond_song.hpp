#pragma once
// Songs written note by note for the view's tests: a 1 ms tick (500 ticks per quarter at 120 bpm), so a
// note's ticks are its milliseconds.
#include <cstdint>

#include "host/midi/song.hpp"

namespace hmp::view::test {

inline midi::Song millisecond_song(std::uint32_t tracks) {
  midi::Song song;
  song.tempo_map = midi::TempoMap::metrical(500, {});
  song.tracks.resize(tracks);
  return song;
}

inline void add_note(midi::Song& song, std::uint32_t track, std::uint64_t start_ms, std::uint64_t ms, int key) {
  midi::Note n;
  n.track = track;
  n.start_tick = start_ms;
  n.end_tick = start_ms + ms;
  n.key = static_cast<std::uint8_t>(key);
  n.velocity = 90;
  song.notes.push_back(n);
  song.tracks[track].note_count++;
  song.tracks[track].keys.add(n.key);
}

}  // namespace hmp::view::test
