#pragma once
// The device tick from SysTick on the core clock: one interrupt per tick period, and the sub-tick
// position the firmware core asks for when a report arrives (BoardSeam::subtick).
#include <cstdint>

namespace hmp::board {

class TickTimer {
 public:
  // The rate must divide the core clock into a whole number of clocks that SysTick's 24-bit reload can
  // hold (at 25 MHz: 1 Hz is too slow, 25 MHz too fast; 1 kHz and 10 kHz are fine).
  static bool valid_rate(std::uint32_t core_hz, std::uint32_t tick_hz);
  // SysTick counts from zero and raises its exception every 1/tick_hz s (valid_rate must hold).
  void start(std::uint32_t core_hz, std::uint32_t tick_hz);
  void stop();
  // Fraction of the present tick elapsed, 2^32 = one tick. 0xFFFFFFFF when the counter has wrapped but
  // the tick interrupt has not run yet, so that tick + subtick never steps back (board.hpp).
  std::uint32_t subtick() const;

 private:
  std::uint32_t reload_ = 0;  // clocks per tick − 1
  std::uint64_t scale_ = 0;   // 2^64 / (reload_ + 1): elapsed clocks → 2^-32 ticks without a division
};

}  // namespace hmp::board
