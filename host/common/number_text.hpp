#pragma once
// A number the user typed (an option's value): the whole text must be a number, finite, and for a count
// an integer within its range.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

namespace hmp {

// `v` as %g writes it, its exponent without a '+' or leading zeros, for a limit quoted in a message: 1e9,
// 1e-7, 2.5e-5, 0.001, 1000.
inline std::string short_number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  const std::string s = text;
  const std::size_t e = s.find('e');
  if (e == std::string::npos) return s;
  std::size_t digits = e + 1;
  const bool negative = s[digits] == '-';
  if (s[digits] == '-' || s[digits] == '+') ++digits;
  while (digits + 1 < s.size() && s[digits] == '0') ++digits;
  return s.substr(0, e + 1) + (negative ? "-" : "") + s.substr(digits);
}

// The number that is the whole of `text` (strtod's syntax), if it is one and finite; else nothing.
inline std::optional<double> finite_number(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// The decimal integer that is the whole of `text`, if it is one within [least, most]; else nothing. Digits
// alone, after an optional '-': no space or '+' before them (which strtol would skip), so that one number
// has few spellings.
inline std::optional<long> whole_number(const std::string& text, long least, long most) {
  const std::size_t first = text.starts_with('-') ? 1 : 0;
  if (text.size() == first || text[first] < '0' || text[first] > '9') return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || v < least || v > most)
    return std::nullopt;
  return v;
}

}  // namespace hmp
