#include "host/common/printable.hpp"

#include <cstdint>
#include <string>

namespace hmp {
namespace {

// The length of the valid UTF-8 sequence starting at s[i], or 0 when the byte there does not start one.
std::size_t sequence_length(std::string_view s, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<std::uint8_t>(s[k]); };
  const std::uint8_t b = byte(i);
  if (b < 0x80) return 1;
  std::size_t n = 0;
  std::uint32_t cp = 0;
  if (b >= 0xC2 && b <= 0xDF)
    n = 2, cp = b & 0x1Fu;
  else if (b >= 0xE0 && b <= 0xEF)
    n = 3, cp = b & 0x0Fu;
  else if (b >= 0xF0 && b <= 0xF4)
    n = 4, cp = b & 0x07u;
  else
    return 0;  // a continuation byte, or a lead byte that can only start an overlong or too large form
  if (i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (byte(i + k) & 0x3Fu);
  }
  if ((n == 3 && cp < 0x800) || (n == 4 && cp < 0x10000)) return 0;  // overlong
  if ((cp >= 0xD800 && cp <= 0xDFFF) || cp > 0x10FFFF) return 0;     // surrogate, past Unicode
  return n;
}

void hex_digits(std::string& out, std::uint8_t b) {
  constexpr char kDigits[] = "0123456789ABCDEF";
  out += kDigits[b >> 4];
  out += kDigits[b & 0xF];
}

void hex(std::string& out, std::uint8_t b) {
  out += "\\x";
  hex_digits(out, b);
}

// Appends the character at bytes[i] made visible, and returns the bytes it took.
std::size_t append_visible(std::string& out, std::string_view bytes, std::size_t i, bool escape_backslash) {
  const auto b = static_cast<std::uint8_t>(bytes[i]);
  const std::size_t n = sequence_length(bytes, i);
  if (n == 0) {
    hex(out, b);
    return 1;
  }
  if (n == 2 && b == 0xC2 && static_cast<std::uint8_t>(bytes[i + 1]) < 0xA0) {
    out += "\\u00";  // a C1 control character (U+0080–U+009F): some terminals act on them
    hex_digits(out, static_cast<std::uint8_t>(bytes[i + 1]));
  } else if (n > 1) {
    out.append(bytes.substr(i, n));
  } else if (b == '\0') {
    out += "\\0";
  } else if (b == '\n') {
    out += "\\n";
  } else if (b == '\r') {
    out += "\\r";
  } else if (b == '\t') {
    out += "\\t";
  } else if (b == '\\' && escape_backslash) {
    out += "\\\\";
  } else if (b < 0x20 || b == 0x7F) {
    hex(out, b);
  } else {
    out += static_cast<char>(b);
  }
  return n;
}
}  // namespace

std::string printable(std::string_view bytes) {
  std::string out;
  out.reserve(bytes.size());
  for (std::size_t i = 0; i < bytes.size();) i += append_visible(out, bytes, i, true);
  return out;
}

std::string terminal_line(std::string_view message, std::size_t max_bytes) {
  std::string out;
  std::size_t i = 0;
  while (i < message.size() && out.size() < max_bytes) i += append_visible(out, message, i, false);
  if (i < message.size()) out += "… (" + std::to_string(message.size() - i) + " bytes more)";
  return out;
}

bool valid_utf8(std::string_view bytes) {
  for (std::size_t i = 0; i < bytes.size();) {
    const std::size_t n = sequence_length(bytes, i);
    if (n == 0) return false;
    i += n;
  }
  return true;
}

}  // namespace hmp
