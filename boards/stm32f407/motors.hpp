#pragma once
// The eight motor outputs: PWM magnitude on TIM9–14 (20 kHz, above hearing), a direction pin each, and
// one enable for every H-bridge. The enable is low from reset (the pin floats until init(), an external
// pull-down holds the bridges off) and goes high only through enable(true); force_safe() drops it and
// zeroes every duty using register writes only, so that fault handlers can call it in any state.
#include <cstdint>

#include "clocks.hpp"
#include "firmware/board.hpp"

namespace hmp::board::stm32 {

class Motors {
 public:
  static constexpr std::uint32_t kPwmHz = 20'000;
  // Per-motor wiring sign: +1 when a positive duty (wind string in) is the bridge's forward direction.
  static constexpr std::int8_t kSign[fw::kMotorCount] = {1, 1, 1, 1, 1, 1, 1, 1};

  void init(const Clocks& clocks);                 // outputs at zero, enable low
  void set(const float (&duty)[fw::kMotorCount]);  // tick context; ignored while disabled
  void enable(bool on);
  bool enabled() const { return enabled_; }
  static void force_safe();  // any context, no RAM state needed

 private:
  std::uint32_t period_[fw::kMotorCount] = {};  // ARR + 1 of each channel's timer
  bool enabled_ = false;
};

// Whether a motor board is plugged in (pins.hpp: kMotorBoardPresent). Call once at start-up.
bool motor_board_present();

}  // namespace hmp::board::stm32
