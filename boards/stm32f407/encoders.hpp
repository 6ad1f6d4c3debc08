#pragma once
// The eight quadrature encoders. Encoders 1–6 are counted by timers in encoder mode (×4: both edges of
// both channels, an 8-sample input filter); 16-bit timers wrap, so read() extends every counter to 32
// bits by the signed 16-bit difference since the last read (right while a motor moves less than 32,767
// counts — 16 pulley turns — per tick). Encoders 7–8 are decoded in software from their pins' interrupts:
// every edge reads both pins and steps the count by the quadrature transition table; a transition that
// changes both pins at once (an edge was missed) is counted in `missed` rather than guessed.
#include <cstdint>

#include "firmware/board.hpp"

namespace hmp::board::stm32 {

class Encoders {
 public:
  void init();
  void read(std::int32_t (&counts)[fw::kMotorCount]);  // tick context
  void on_pin_edge(int encoder);                       // EXTI handlers: encoder 6 or 7 (0-based)
  std::uint32_t missed() const { return missed_; }

  // The quadrature step from the previous (a, b) state to the present one: +1, −1, 0 (no change), or
  // kInvalid (both changed). State = a << 1 | b; forward is 00 → 01 → 11 → 10 → 00.
  static constexpr std::int8_t kInvalid = 2;
  static constexpr std::int8_t step(std::uint8_t from, std::uint8_t to) {
    constexpr std::int8_t table[16] = {0,  +1,       -1, kInvalid, -1,       0,  kInvalid, +1,
                                       +1, kInvalid, 0,  -1,       kInvalid, -1, +1,       0};
    return table[(from & 3u) << 2 | (to & 3u)];
  }

 private:
  std::uint32_t last_hw_[6] = {};
  std::int32_t count_[fw::kMotorCount] = {};
  volatile std::int32_t soft_count_[2] = {};
  std::uint8_t soft_state_[2] = {};
  volatile std::uint32_t missed_ = 0;
};

}  // namespace hmp::board::stm32
