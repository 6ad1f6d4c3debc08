#include <cstdio>

#include "host/midi/smf_detail.hpp"

namespace hmp::midi::detail {

std::string place(std::int64_t chunk, std::uint64_t offset) {
  char buf[64];
  if (chunk >= 0) {
    std::snprintf(buf, sizeof buf, "track %lld at byte 0x%llx", static_cast<long long>(chunk),
                  static_cast<unsigned long long>(offset));
  } else {
    std::snprintf(buf, sizeof buf, "byte 0x%llx", static_cast<unsigned long long>(offset));
  }
  return buf;
}

void WarningLog::add(std::int64_t chunk, std::uint64_t offset, std::string_view text) {
  if (list_.size() >= kMaxWarnings) {
    ++suppressed_;
    return;
  }
  std::string message = place(chunk, offset);
  message += ": ";
  message += text;
  list_.push_back(Warning{chunk, offset, std::move(message)});
}

std::vector<Warning> WarningLog::take() {
  if (suppressed_ > 0) {
    list_.push_back(Warning{-1, 0, std::to_string(suppressed_) + " more warnings not shown"});
    suppressed_ = 0;
  }
  return std::move(list_);
}

}  // namespace hmp::midi::detail
