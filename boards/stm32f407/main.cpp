// The stm32f407 firmware image: clocks (with their fallbacks), the board, the watchdog, then the main
// loop — the core's background work, feeding the watchdog while the tick advances, the LEDs, `wfi`.
#include <new>

#include "clocks.hpp"
#include "registers.hpp"
#include "stm32f407_board.hpp"
#include "watchdog.hpp"

namespace {

namespace stm32 = hmp::board::stm32;
using stm32::Stm32Board;

// The board with the core (~21 KiB, in SRAM: stm32f407.ld says why), built in main() once the clock is
// known. The handlers run only after start() has enabled the interrupts.
alignas(Stm32Board) unsigned char g_board_storage[sizeof(Stm32Board)];
Stm32Board* g_board = nullptr;
stm32::OtgMmio g_otg_registers;
stm32::UsbController g_usb{g_otg_registers};

void clear_exti(unsigned line) { hmp::board::reg(stm32::exti::kPr) = 1u << line; }

}  // namespace

extern "C" {
void SysTick_Handler() { g_board->on_tick(); }
void USART2_IRQHandler() { g_board->on_usart(); }
// Encoder 7 on lines 0–1, encoder 8 on lines 2–3 (pins.hpp).
void EXTI0_IRQHandler() { clear_exti(0), g_board->on_encoder_edge(6); }
void EXTI1_IRQHandler() { clear_exti(1), g_board->on_encoder_edge(6); }
void EXTI2_IRQHandler() { clear_exti(2), g_board->on_encoder_edge(7); }
void EXTI3_IRQHandler() { clear_exti(3), g_board->on_encoder_edge(7); }
void EXTI9_5_IRQHandler() { g_board->on_estop_edge(); }
void OTG_FS_IRQHandler() { g_board->on_usb(); }
}

int main() {
  const bool watchdog_reset = stm32::Watchdog::take_reset_flag();
  const stm32::Clocks clocks = stm32::setup_clocks();
  const bool usb = stm32::start_usb_controller(g_usb, clocks);
  std::uint8_t flags = usb ? 0 : hmp::protocol::board_no_usb;
  if (clocks.source != stm32::ClockSource::hse_pll) flags |= hmp::protocol::board_clock_fallback;
  if (watchdog_reset) flags |= hmp::protocol::board_watchdog_reset;
  if (!stm32::motor_board_present()) flags |= hmp::protocol::board_no_drive;

  g_board = new (g_board_storage) Stm32Board(clocks, flags, usb ? &g_usb : nullptr);
  g_board->start();
  stm32::Watchdog::start();

  std::uint32_t fed_at = g_board->ticks();
  for (;;) {
    while (g_board->poll()) {
    }
    // Fed only while the tick advances: a stuck tick or a stuck loop both end in a reset.
    if (const std::uint32_t now = g_board->ticks(); now != fed_at) {
      stm32::Watchdog::feed();
      fed_at = now;
    }
    g_board->show_state();
    // An interrupt between the poll above and the wfi is seen at the next tick at the latest.
    asm volatile("wfi" ::: "memory");
  }
}
