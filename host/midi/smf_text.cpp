#include "host/midi/smf_detail.hpp"

namespace hmp::midi::detail {
namespace {

// Length of the well-formed UTF-8 sequence at t[i] (shortest form, no surrogates, ≤ U+10FFFF), or 0.
std::size_t utf8_sequence(std::span<const std::uint8_t> t, std::size_t i) {
  const std::uint8_t b = t[i];
  std::size_t n;
  std::uint8_t lo = 0x80, hi = 0xBF;  // allowed range of the second byte
  if (b >= 0xC2 && b <= 0xDF) {
    n = 2;
  } else if (b >= 0xE0 && b <= 0xEF) {
    n = 3;
    if (b == 0xE0) lo = 0xA0;
    if (b == 0xED) hi = 0x9F;
  } else if (b >= 0xF0 && b <= 0xF4) {
    n = 4;
    if (b == 0xF0) lo = 0x90;
    if (b == 0xF4) hi = 0x8F;
  } else {
    return 0;
  }
  if (i + n > t.size()) return 0;
  if (t[i + 1] < lo || t[i + 1] > hi) return 0;
  for (std::size_t k = 2; k < n; ++k) {
    if (t[i + k] < 0x80 || t[i + k] > 0xBF) return 0;
  }
  return n;
}

bool is_utf8(std::span<const std::uint8_t> t) {
  for (std::size_t i = 0; i < t.size();) {
    if (t[i] < 0x80) {
      ++i;
    } else {
      const std::size_t n = utf8_sequence(t, i);
      if (n == 0) return false;
      i += n;
    }
  }
  return true;
}

}  // namespace

std::string text_to_utf8(std::span<const std::uint8_t> text) {
  std::size_t n = text.size();
  while (n > 0 && (text[n - 1] == 0 || text[n - 1] == ' ' || text[n - 1] == '\t' || text[n - 1] == '\r' ||
                   text[n - 1] == '\n')) {
    --n;
  }
  std::size_t first = 0;
  while (first < n && (text[first] == ' ' || text[first] == '\t')) ++first;
  text = text.subspan(first, n - first);
  const bool utf8 = is_utf8(text);
  std::string out;
  out.reserve(utf8 ? text.size() : 2 * text.size());
  for (const std::uint8_t b : text) {
    if (b < 0x20 || b == 0x7F) {
      out += ' ';  // tabs, newlines, NULs inside a name: keep it on one line
    } else if (b < 0x80 || utf8) {
      out += static_cast<char>(b);
    } else {  // Latin-1 code point b as two UTF-8 bytes
      out += static_cast<char>(0xC0 | (b >> 6));
      out += static_cast<char>(0x80 | (b & 0x3F));
    }
  }
  return out;
}

}  // namespace hmp::midi::detail
