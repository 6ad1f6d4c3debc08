#pragma once
// The clock tree (RM0090 §6): HSE 8 MHz crystal → PLL → 168 MHz core, 48 MHz for USB, APB1 42 MHz
// (its timers 84 MHz), APB2 84 MHz (its timers 168 MHz), five flash wait states. Every wait is bounded;
// what does not start is reported, never waited for:
//   crystal does not start      → the PLL runs from the internal 16 MHz oscillator (HSI, ±1 % trimmed):
//                                 168 MHz as before, the UART works, USB does not (it needs ±0.25 %);
//   PLL does not lock either    → the core stays on HSI at 16 MHz: the UART works, USB does not, and
//                                 the drive does not fit a tick (the board keeps its motors off);
//   the RCC does not answer     → (HSIRDY, set by hardware from reset, reads 0: only an emulator without
//                                 an RCC model does this, e.g. QEMU's netduinoplus2) the clock is
//                                 whatever the emulator runs; we assume the 168 MHz we asked for.
#include <cstdint>

namespace hmp::board::stm32 {

enum class ClockSource : std::uint8_t { hse_pll, hsi_pll, hsi, rcc_absent };

struct Clocks {
  ClockSource source = ClockSource::hsi;
  std::uint32_t core_hz = 16'000'000;        // HCLK: the core, SysTick
  std::uint32_t apb1_timer_hz = 16'000'000;  // TIM2–5, TIM12–14
  std::uint32_t apb2_timer_hz = 16'000'000;  // TIM1, TIM8–11
  std::uint32_t usart2_hz = 16'000'000;      // APB1
  bool usb_clock_ok = false;                 // 48 MHz from the crystal
  bool full_speed() const { return core_hz == 168'000'000; }
};

// Run once from reset, before anything depends on the clock.
Clocks setup_clocks();

const char* clock_source_name(ClockSource source);

}  // namespace hmp::board::stm32
