#pragma once
// A benchmark's numeric arguments: the value, or one line saying which argument is wrong and exit 2
// (a prefix such as "5x" or a value out of range would otherwise measure something nobody asked for).
#include <cerrno>  // program_invocation_short_name (glibc)
#include <cstdio>
#include <cstdlib>
#include <optional>

#include "host/common/number_text.hpp"
#include "host/common/printable.hpp"

namespace hmp::bench {

inline double number_argument(const char* name, const char* text, double least, double most) {
  const std::optional<double> v = finite_number(text);
  if (!v || *v < least || *v > most) {
    std::fprintf(stderr, "%s: %s: '%s' is not a number from %g to %g\n", program_invocation_short_name, name,
                 printable(text).c_str(), least, most);
    std::exit(2);
  }
  return *v;
}

inline long count_argument(const char* name, const char* text, long least, long most) {
  const std::optional<long> v = whole_number(text, least, most);
  if (!v) {
    std::fprintf(stderr, "%s: %s: '%s' is not a whole number from %ld to %ld\n", program_invocation_short_name, name,
                 printable(text).c_str(), least, most);
    std::exit(2);
  }
  return *v;
}

}  // namespace hmp::bench
