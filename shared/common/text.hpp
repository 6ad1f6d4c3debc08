#pragma once
// ASCII text helpers for name lookups in freestanding code (no locale: preset and mode names are ASCII).

namespace hmp::text {

constexpr char ascii_lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

// Case-insensitive equality of two NUL-terminated strings; a null pointer equals nothing.
constexpr bool iequals(const char* a, const char* b) {
  if (a == nullptr || b == nullptr) return false;
  for (; *a != '\0' && *b != '\0'; ++a, ++b) {
    if (ascii_lower(*a) != ascii_lower(*b)) return false;
  }
  return *a == *b;
}

}  // namespace hmp::text
