#pragma once
// host/view/: the music animation (docs/view.md). This folder holds what the window shows,
// independent of how it is drawn: which notes are visible now (note_index), where each bar goes and in
// which colour (roll_layout), and which bar is under a cursor (roll_layout's pick). The drawing (SDL2 +
// OpenGL) is a module on top of it; the player hands it the song, the clock and its state, nothing more.
//
// NoteIndex: the notes of every track sorted by start, with the running maximum of their ends, so that
// the notes sounding in any window [t0, t1) are found by binary search: the first note whose running
// maximum end passes t0 is where they can begin, and they end before the first note starting at t1. The
// cost of a frame is the notes it shows (plus the short notes among them that ended), not the song's length.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "host/midi/song.hpp"

namespace hmp::view {

// One note bar: song times in µs (from the tempo map, so tempo changes are in), key and velocity.
struct Bar {
  std::int64_t start_us = 0, end_us = 0;
  std::uint8_t key = 0;
  std::uint8_t velocity = 0;
  std::uint32_t track = 0;
};

class NoteIndex {
 public:
  explicit NoteIndex(const midi::Song& song);

  std::size_t tracks() const { return bars_.size(); }
  std::span<const Bar> bars(std::uint32_t track) const { return bars_.at(track); }

  // The bars of `track` that overlap [t0_us, t1_us): start < t1 and end > t0 (a zero-length note counts
  // while t0 ≤ its time < t1). `out` is cleared first and filled in start order; returns its size.
  std::size_t visible(std::uint32_t track, std::int64_t t0_us, std::int64_t t1_us, std::vector<Bar>& out) const;

  // Whether a bar sounds at `t_us` (start ≤ t < end): derived from the time alone, so pause and seek can
  // never leave a bar lit.
  static bool sounding(const Bar& b, std::int64_t t_us) { return b.start_us <= t_us && t_us < b.end_us; }

 private:
  std::vector<std::vector<Bar>> bars_;              // per track, by start
  std::vector<std::vector<std::int64_t>> max_end_;  // per track: max end of bars [0, i]
};

}  // namespace hmp::view
