#include "host/common/time_format.hpp"

#include <fmt/format.h>

namespace hmp {

std::string format_time(std::int64_t us) {
  if (us < 0) us = 0;
  const std::int64_t tenths = us / 100'000;
  return fmt::format("{}:{:02}.{}", tenths / 600, tenths / 10 % 60, tenths % 10);
}

}  // namespace hmp
