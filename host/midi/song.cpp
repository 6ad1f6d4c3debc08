#include "host/midi/song.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>

#include "host/midi/gm.hpp"

namespace hmp::midi {

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

bool is_sound_controller(std::uint8_t number) {
  return std::find(std::begin(kSoundControllers), std::end(kSoundControllers), number) != std::end(kSoundControllers);
}

std::string controller_name(std::uint8_t number) {
  switch (number) {
    case 0:
    case 32: return "bank select";
    case 1: return "modulation";
    case 6:
    case 38: return "data entry";
    case 100:
    case 101: return "RPN";
    case 7: return "volume";
    case 10: return "pan";
    case 11: return "expression";
    case 64: return "sustain";
    case 66: return "sostenuto";
    case 67: return "soft pedal";
    case 91: return "reverb";
    case 93: return "chorus";
    case 120: return "all sound off";
    case 121: return "reset controllers";
    case 123: return "all notes off";
    default: return "CC " + std::to_string(number);
  }
}

std::vector<std::string> controllers_used(const Song& song, std::uint32_t track) {
  std::vector<std::string> out;
  if (track >= song.tracks.size()) return out;
  const Track& t = song.tracks[track];
  bool cc[128] = {}, bend = false, pressure = false;
  int first_program[16], programs_changed[16] = {};
  std::fill(std::begin(first_program), std::end(first_program), -1);
  for (const Control& c : song.controls) {
    if (!t.has_channel(c.channel)) continue;
    switch (c.kind) {
      case Control::Kind::controller: cc[c.number & 0x7F] = true; break;
      case Control::Kind::pitch_bend: bend = true; break;
      case Control::Kind::pressure: pressure = true; break;
      case Control::Kind::program: {
        int& first = first_program[c.channel & 0x0F];
        if (first < 0)
          first = c.number;
        else if (first != c.number)
          programs_changed[c.channel & 0x0F] = 1;
        break;
      }
    }
  }
  for (int n = 0; n < 128; ++n) {
    const std::string name = controller_name(static_cast<std::uint8_t>(n));
    if (cc[n] && std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);  // MSB and LSB: one name
  }
  if (bend) out.push_back("pitch bend");
  if (pressure) out.push_back("channel pressure");
  if (std::any_of(std::begin(programs_changed), std::end(programs_changed), [](int n) { return n != 0; })) {
    out.push_back("program changes");  // to another program: the first one only sets the instrument
  }
  return out;
}

}  // namespace hmp::midi
