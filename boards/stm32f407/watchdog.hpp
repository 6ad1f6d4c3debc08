#pragma once
// The independent watchdog (RM0090 §21): clocked by the LSI oscillator, it resets the chip unless fed
// within its timeout, even if the main clock has stopped. The board feeds it from the main loop only
// when the tick has advanced since the last feed, so a stuck tick interrupt and a stuck main loop both
// end in a reset — into the safe state, as every reset does (the motor enable is low from reset).
#include <cstdint>

namespace hmp::board::stm32 {

class Watchdog {
 public:
  // Nominal timeout; the LSI's 17–47 kHz spread makes it 68–188 ms. Once started it cannot be stopped.
  static constexpr std::uint32_t kTimeoutMs = 100;
  static void start();
  static void feed();
  // Whether the last reset came from the watchdog (read once at start-up; clears the reset flags).
  static bool take_reset_flag();
};

}  // namespace hmp::board::stm32
