#pragma once
// Little-endian byte access for fixed wire layouts. Never reads or writes past the span it is given:
// callers check sizes first; these helpers only assemble bytes.
#include <cstddef>
#include <cstdint>

namespace hmp::bytes {

inline std::uint16_t get_u16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }
inline std::uint32_t get_u24(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16);
}
inline std::uint32_t get_u32(const std::uint8_t* p) { return get_u24(p) | (static_cast<std::uint32_t>(p[3]) << 24); }
inline std::uint64_t get_u64(const std::uint8_t* p) {
  return static_cast<std::uint64_t>(get_u32(p)) | (static_cast<std::uint64_t>(get_u32(p + 4)) << 32);
}
inline float get_f32(const std::uint8_t* p) {
  const std::uint32_t u = get_u32(p);
  float f;
  __builtin_memcpy(&f, &u, sizeof f);
  return f;
}

inline void put_u16(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v);
  p[1] = static_cast<std::uint8_t>(v >> 8);
}
inline void put_u24(std::uint8_t* p, std::uint32_t v) {
  p[0] = static_cast<std::uint8_t>(v);
  p[1] = static_cast<std::uint8_t>(v >> 8);
  p[2] = static_cast<std::uint8_t>(v >> 16);
}
inline void put_u32(std::uint8_t* p, std::uint32_t v) {
  put_u24(p, v);
  p[3] = static_cast<std::uint8_t>(v >> 24);
}
inline void put_u64(std::uint8_t* p, std::uint64_t v) {
  put_u32(p, static_cast<std::uint32_t>(v));
  put_u32(p + 4, static_cast<std::uint32_t>(v >> 32));
}
inline void put_f32(std::uint8_t* p, float f) {
  std::uint32_t u;
  __builtin_memcpy(&u, &f, sizeof u);
  put_u32(p, u);
}

}  // namespace hmp::bytes
