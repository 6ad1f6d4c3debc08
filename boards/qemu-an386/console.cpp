#include "console.hpp"

#include "semihosting.hpp"

namespace hmp::board {

void Line::put(char c) {
  if (len_ < kCapacity) buf_[len_++] = c;
}

Line& Line::text(const char* s) {
  while (*s != '\0') put(*s++);
  return *this;
}

Line& Line::u32(std::uint32_t v) {
  char digits[10];
  std::size_t n = 0;
  do {
    digits[n++] = static_cast<char>('0' + v % 10);
    v /= 10;
  } while (v != 0);
  while (n > 0) put(digits[--n]);
  return *this;
}

Line& Line::i32(std::int32_t v) {
  if (v < 0) {
    put('-');
    // Negate in unsigned arithmetic so INT32_MIN does not overflow.
    return u32(0u - static_cast<std::uint32_t>(v));
  }
  return u32(static_cast<std::uint32_t>(v));
}

Line& Line::hex(std::uint32_t v) {
  text("0x");
  for (int shift = 28; shift >= 0; shift -= 4) put("0123456789abcdef"[(v >> shift) & 0xFu]);
  return *this;
}

Line& Line::hex_bytes(const std::uint8_t* bytes, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) {
    put("0123456789abcdef"[bytes[i] >> 4]);
    put("0123456789abcdef"[bytes[i] & 0xFu]);
  }
  return *this;
}

Line& Line::fixed(float v, unsigned decimals) {
  if (v != v) return text("nan");
  if (v < 0.0f) {
    put('-');
    v = -v;
  }
  // Beyond 2^32 the integer part cannot be printed this way; such values are errors in our outputs.
  if (v >= 4294967296.0f) return text("inf");
  if (decimals > 9) decimals = 9;
  std::uint64_t scale = 1;
  for (unsigned i = 0; i < decimals; ++i) scale *= 10;
  // Split first so the rounding happens on the fraction only (a float has too few bits for v·10^9).
  auto whole = static_cast<std::uint64_t>(v);
  const float frac = v - static_cast<float>(whole);
  auto frac_scaled = static_cast<std::uint64_t>(static_cast<double>(frac) * static_cast<double>(scale) + 0.5);
  if (frac_scaled >= scale) {
    frac_scaled -= scale;
    ++whole;
  }
  if (whole > 0xFFFFFFFFu) return text("inf");
  u32(static_cast<std::uint32_t>(whole));
  if (decimals == 0) return *this;
  put('.');
  for (std::uint64_t div = scale / 10; div > 0; div /= 10) put(static_cast<char>('0' + (frac_scaled / div) % 10));
  return *this;
}

void Line::print() {
  buf_[len_] = '\n';
  buf_[len_ + 1] = '\0';
  semihost::write0(buf_);
  len_ = 0;
}

}  // namespace hmp::board
