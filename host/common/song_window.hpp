#pragma once
// The passage of a song that --from/--to pick, in seconds of the song: both times finite and ≥ 0, the
// start before the song's end and before the end, and an end past the song's held to it. One rule for
// every command that takes a window, so that `--to 1e300` means "to the end" everywhere instead of a
// product that overflows an integer.
#include <cstdint>
#include <optional>

namespace hmp {

struct SongWindowUs {
  std::int64_t begin_us = 0, end_us = 0;
};

// Throws BadInput naming the option when a given time is not finite and ≥ 0, or the end is at or before
// the start (where the song's end is not known yet, as for a playlist's songs).
void check_window_times(std::optional<double> from_s, std::optional<double> to_s);

// Throws BadInput when --from is at or past the end of a song that ends at `song_end_us`.
void check_start_in_song(std::optional<double> from_s, std::int64_t song_end_us);

// The window within a song that ends at `song_end_us` (> 0): the checks above, then BadInput when --from is
// at or past the song's end; no --to, or one past the song's end, is the song's end.
SongWindowUs song_window(std::optional<double> from_s, std::optional<double> to_s, std::int64_t song_end_us);

// s seconds (finite, ≥ 0) in µs, saturated where they would leave a 64-bit integer (292,000 years).
std::int64_t saturated_us(double s);

}  // namespace hmp
