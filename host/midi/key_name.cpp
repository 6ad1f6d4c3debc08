#include "host/midi/key_name.hpp"

#include <cctype>

namespace hmp::midi {
namespace {

constexpr const char* kNames[] = {"C", "C#", "D", "D#", "E", "F", "F#", "G", "G#", "A", "A#", "B"};
constexpr int kLetterSemitone[] = {9, 11, 0, 2, 4, 5, 7};  // A … G

// A whole number with an optional leading '-', nothing else; nullopt when it is not one or is far out.
std::optional<int> whole_number(std::string_view text) {
  const bool minus = !text.empty() && text[0] == '-';
  if (minus) text.remove_prefix(1);
  if (text.empty() || text.size() > 3) return std::nullopt;
  int v = 0;
  for (const char c : text) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return std::nullopt;
    v = v * 10 + (c - '0');
  }
  return minus ? -v : v;
}

}  // namespace

std::string key_name(int key) {
  if (key < 0) return "-";
  return std::string(kNames[key % 12]) + std::to_string(key / 12 - 1);
}

std::optional<int> parse_key(std::string_view text) {
  std::optional<int> key = whole_number(text);
  if (!key && !text.empty()) {
    const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(text[0])));
    if (letter < 'A' || letter > 'G') return std::nullopt;
    int semitone = kLetterSemitone[letter - 'A'];
    text.remove_prefix(1);
    if (!text.empty() && (text[0] == '#' || text[0] == 'b')) {
      semitone += text[0] == '#' ? 1 : -1;
      text.remove_prefix(1);
    }
    const std::optional<int> octave = whole_number(text);
    if (!octave) return std::nullopt;
    key = (*octave + 1) * 12 + semitone;
  }
  if (!key || *key < 0 || *key > 127) return std::nullopt;
  return key;
}

}  // namespace hmp::midi
