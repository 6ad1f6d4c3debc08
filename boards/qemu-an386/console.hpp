#pragma once
// Text output over semihosting without printf: newlib's stdio would bring in malloc and file syscalls.
// A Line collects pieces in a fixed buffer (overlong text is cut, never overflows) and prints them
// with one host call.
#include <cstddef>
#include <cstdint>

namespace hmp::board {

class Line {
 public:
  Line& text(const char* s);
  Line& u32(std::uint32_t v);
  Line& i32(std::int32_t v);
  Line& hex(std::uint32_t v);                                     // 0x + 8 digits
  Line& hex_bytes(const std::uint8_t* bytes, std::size_t count);  // two digits per byte, no prefix
  // Fixed-point decimal with `decimals` digits (≤ 9), rounded; prints nan/inf by name.
  Line& fixed(float v, unsigned decimals = 6);
  // Appends '\n' and writes the line; the Line is empty afterwards.
  void print();

 private:
  void put(char c);
  static constexpr std::size_t kCapacity = 160;  // fits a 64-byte report in hex plus a prefix
  char buf_[kCapacity + 2] = {};                 // + '\n' + NUL
  std::size_t len_ = 0;
};

}  // namespace hmp::board
