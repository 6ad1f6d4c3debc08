// The qemu-an386 firmware image: the firmware core on SysTick (the tick) and UART0 (the host link,
// framed reports) or, with link=net, the Ethernet controller (a report per frame), logging over
// semihosting. Options come from the semihosting command line (QEMU
// -append "…", README.md): tick rate, the output trace for tests, and an exit when the host has gone
// quiet. Without exit-idle-ms it runs until QEMU is stopped.
#include <new>

#include "an386_board.hpp"
#include "console.hpp"
#include "options.hpp"
#include "semihosting.hpp"

namespace {

using hmp::board::An386Board;
using hmp::board::Line;

// The board (and the core in it, ~12 KiB) is built in main() once the options are known; static
// storage, no heap. The handlers run only after main() has started the interrupts.
alignas(An386Board) unsigned char g_board_storage[sizeof(An386Board)];
An386Board* g_board = nullptr;

}  // namespace

extern "C" void SysTick_Handler() { g_board->on_tick(); }
extern "C" void UART0_RX_Handler() { g_board->on_uart_rx(); }
extern "C" void UART0_TX_Handler() { g_board->on_uart_tx(); }
extern "C" void ETHERNET_Handler() { g_board->on_ethernet(); }

int main() {
  const hmp::board::Options opt = hmp::board::read_options();
  if (opt.error != nullptr) return hmp::board::kExitBadOption;
  // Laid out by hand (one log line, its fields side by side), so the formatter leaves it:
  // clang-format off
  Line().text("HMP qemu-an386 firmware ").u32(hmp::fw::kFirmwareMajor).text(".").u32(hmp::fw::kFirmwareMinor)
      .text(".").u32(hmp::fw::kFirmwarePatch).text(" tick_hz=").u32(opt.tick_hz)
      .text(" trace=").text(opt.trace ? "on" : "off").text(" exit_idle_ms=").u32(opt.exit_idle_ms)
      .text(" listen_after_ms=").u32(opt.listen_after_ms).text(" link=").text(opt.net ? "net" : "uart").print();
  // clang-format on

  g_board = new (g_board_storage) An386Board(opt.tick_hz, opt.trace);
  g_board->listen_from_tick(
      static_cast<std::uint32_t>(static_cast<std::uint64_t>(opt.listen_after_ms) * opt.tick_hz / 1000));
  if (!g_board->start_link(opt.net)) {
    Line().text("link=net: no Ethernet controller answers at its address").print();
    return hmp::board::kExitBadOption;
  }
  g_board->start_tick();

  const auto idle_ticks = static_cast<std::uint32_t>(static_cast<std::uint64_t>(opt.exit_idle_ms) * opt.tick_hz / 1000);
  std::uint32_t seen_rx = g_board->rx_activity();
  std::uint32_t last_rx_tick = 0;
  for (;;) {
    while (g_board->poll()) {
    }
    g_board->drain_trace(false);
    if (idle_ticks != 0) {
      const std::uint32_t now = g_board->ticks();
      const std::uint32_t rx = g_board->rx_activity();
      if (rx != seen_rx || g_board->rx_paused()) {  // held-back bytes are not silence
        seen_rx = rx;
        last_rx_tick = now;
      } else if (now - last_rx_tick >= idle_ticks) {
        break;
      }
    }
    // An interrupt that lands between the checks (or the poll) above and the wfi is seen one tick later
    // at most: the tick hands voices to prepare kPrepareAheadMs ahead, and reports wait in the outbox.
    asm volatile("wfi" ::: "memory");
  }
  g_board->stop();
  g_board->drain_trace(true);
  Line().text("exit: no byte from the host for ").u32(opt.exit_idle_ms).text(" ms").print();
  g_board->print_summary();
  return hmp::board::semihost::kExitOk;
}
