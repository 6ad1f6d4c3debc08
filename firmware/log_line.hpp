#pragma once
// One log line built without printf (freestanding): text and unsigned decimals into a fixed buffer,
// silently truncated at the end.
#include <cstddef>
#include <cstdint>

namespace hmp::fw {

class LogLine {
 public:
  LogLine& text(const char* s) {
    while (s != nullptr && *s != '\0' && len_ < kMax) buf_[len_++] = *s++;
    buf_[len_] = '\0';
    return *this;
  }
  LogLine& num(std::uint64_t v) {
    char digits[20];
    std::size_t n = 0;
    do {
      digits[n++] = static_cast<char>('0' + v % 10);
      v /= 10;
    } while (v != 0);
    while (n > 0 && len_ < kMax) buf_[len_++] = digits[--n];
    buf_[len_] = '\0';
    return *this;
  }
  const char* c_str() const { return buf_; }

 private:
  static constexpr std::size_t kMax = 95;
  char buf_[kMax + 1] = {};
  std::size_t len_ = 0;
};

}  // namespace hmp::fw
