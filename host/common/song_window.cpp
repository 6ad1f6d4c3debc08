#include "host/common/song_window.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "host/common/error.hpp"

namespace hmp {

void check_window_times(std::optional<double> from_s, std::optional<double> to_s) {
  if (from_s && !(std::isfinite(*from_s) && *from_s >= 0))
    throw BadInput(fmt::format("--from {}: must be seconds, finite and ≥ 0", *from_s));
  if (to_s && !(std::isfinite(*to_s) && *to_s >= 0))
    throw BadInput(fmt::format("--to {}: must be seconds, finite and ≥ 0", *to_s));
  if (to_s && *to_s <= from_s.value_or(0.0))
    throw BadInput(fmt::format("--from {} --to {}: empty window", from_s.value_or(0.0), *to_s));
}

void check_start_in_song(std::optional<double> from_s, std::int64_t song_end_us) {
  const double end_s = static_cast<double>(song_end_us) * 1e-6;
  if (from_s && *from_s >= end_s) throw BadInput(fmt::format("--from {}: the song ends at {:.3f} s", *from_s, end_s));
}

SongWindowUs song_window(std::optional<double> from_s, std::optional<double> to_s, std::int64_t song_end_us) {
  check_window_times(from_s, to_s);
  check_start_in_song(from_s, song_end_us);
  const double end_s = static_cast<double>(song_end_us) * 1e-6;
  SongWindowUs w;
  w.begin_us = from_s ? saturated_us(*from_s) : 0;
  w.end_us = to_s && *to_s < end_s ? saturated_us(*to_s) : song_end_us;
  if (w.end_us <= w.begin_us)  // a window shorter than a microsecond
    throw BadInput(fmt::format("--from {} --to {}: empty window", from_s.value_or(0.0), to_s.value_or(end_s)));
  return w;
}

std::int64_t saturated_us(double s) {
  constexpr double kLimit = 9.2e12;  // s: 9.2·10¹⁸ µs, just inside a signed 64-bit integer
  return s >= kLimit ? std::numeric_limits<std::int64_t>::max() : std::llround(s * 1e6);
}

}  // namespace hmp
