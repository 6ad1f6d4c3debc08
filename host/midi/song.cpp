#include "host/midi/song.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>

#include "host/midi/gm.hpp"

namespace hmp::midi {

int Track::distinct_keys() const { return std::popcount(keys[0]) + std::popcount(keys[1]); }

int Track::key_min() const {
  if (keys[0] != 0) return std::countr_zero(keys[0]);
  if (keys[1] != 0) return 64 + std::countr_zero(keys[1]);
  return -1;
}

int Track::key_max() const {
  if (keys[1] != 0) return 127 - std::countl_zero(keys[1]);
  if (keys[0] != 0) return 63 - std::countl_zero(keys[0]);
  return -1;
}

std::vector<Note> Song::track_notes(std::uint32_t track) const {
  std::vector<Note> out;
  if (track < tracks.size()) out.reserve(tracks[track].note_count);
  for (const Note& n : notes) {
    if (n.track == track) out.push_back(n);
  }
  return out;
}

namespace {

bool contains_ci(std::string_view hay, std::string_view needle) {
  if (needle.empty()) return false;
  const auto it = std::search(hay.begin(), hay.end(), needle.begin(), needle.end(), [](char a, char b) {
    return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b));
  });
  return it != hay.end();
}

}  // namespace

std::optional<std::uint32_t> find_track(const Song& song, std::string_view query) {
  std::uint32_t index = 0;
  const auto [end, ec] = std::from_chars(query.data(), query.data() + query.size(), index);
  if (ec == std::errc() && end == query.data() + query.size()) {
    if (index < song.tracks.size()) return index;
    return std::nullopt;
  }
  std::optional<std::uint32_t> first_match;
  for (const Track& t : song.tracks) {
    const bool named = contains_ci(t.name, query);
    const bool instrument = t.note_count > 0 && contains_ci(gm_instrument_name(t.program(), t.channel()), query);
    if (!named && !instrument) continue;
    if (t.note_count > 0) return t.index;
    if (!first_match) first_match = t.index;
  }
  return first_match;
}

}  // namespace hmp::midi
