#pragma once
// A number the user typed (an option's value): the whole text must be a finite number.
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>

namespace hmp {

// The number that is the whole of `text` (strtod's syntax), if it is one and finite; else nothing.
inline std::optional<double> finite_number(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

}  // namespace hmp
