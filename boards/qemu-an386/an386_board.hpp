#pragma once
// The qemu-an386 board: the firmware core (firmware/core.hpp) on SysTick and UART0 (or the Ethernet
// controller: net_link.hpp), logging over semihosting. Fills in the BoardSeam; the images' main() and interrupt
// handlers call in here.
//
// Priorities: SysTick (the tick) is the highest; the UART interrupts sit below it, so a report's
// arrival never interrupts a tick half-way and the tick is never delayed by the line. The main loop
// (thread mode) runs the core's background work (poll(): encoding and sending the reports the tick
// queued, preparing the voices of the next notes), writes the optional trace and sleeps in `wfi`.
#include <cstdint>

#include "firmware/core.hpp"
#include "output_trace.hpp"
#include "boards/cortex-m/serial_link.hpp"
#include "net_link.hpp"
#include "boards/cortex-m/systick_timer.hpp"
#include "uart.hpp"

namespace hmp::board {

// Motors and encoders simulated by the bench image, so that the core's SPIDAR drive runs: the drive reads
// `counts` (the bench writes them between ticks) and leaves its duties in `duty`. The firmware image has
// no motors (the board is built without this, and the core skips the drive).
struct BenchMotors {
  std::int32_t counts[fw::kMotorCount]{};
  float duty[fw::kMotorCount]{};
};

class An386Board {
 public:
  using Link = SerialLink<CmsdkUart>;
  An386Board(std::uint32_t tick_hz, bool trace, BenchMotors* motors = nullptr, const fw::DriveParams& drive = {});
  An386Board(const An386Board&) = delete;
  An386Board& operator=(const An386Board&) = delete;

  // The host link and its interrupts: UART0, or the Ethernet controller when `net` (false when it has none).
  bool start_link(bool net = false);
  void start_tick();  // SysTick interrupt at the tick rate
  // Until tick `tick` the UART drops what it receives, as the UART of a board that is still starting
  // does (a real USART that is not enabled yet loses the bytes; this one would otherwise hold them).
  void listen_from_tick(std::uint32_t tick) { listen_from_tick_ = tick; }
  void stop();  // no more ticks or UART interrupts

  // Interrupt handlers.
  void on_tick();  // one device tick: core.on_tick(), then lets the UART take the next report
  void on_uart_rx() {
    if (ticks_ < listen_from_tick_) return drop_rx();
    link_.on_rx_interrupt();
  }
  void on_uart_tx() { link_.on_tx_interrupt(); }
  void on_ethernet() {
    if (ticks_ < listen_from_tick_) {
      rx_lost_ += net_.drop_received();
      return;
    }
    net_.on_interrupt();
  }

  // Main loop.
  bool poll() { return core_.poll(); }  // the core's background work; true if there was any
  void drain_trace(bool all) {
    if (tracing_) trace_.drain(all);
  }
  std::uint32_t ticks() const { return ticks_; }  // ticks run so far (= core.tick() from first tick 0)
  void print_summary() const;

  fw::Core& core() { return core_; }
  // Changes with every byte (UART) or frame (Ethernet) received: the exit-when-idle option watches it.
  std::uint32_t rx_activity() const { return net_on_ ? net_.rx_count() : link_.rx_bytes(); }
  // Reception is held back for a full inbox (reports are waiting in the UART or the controller).
  bool rx_paused() const { return net_on_ ? net_.rx_paused() : link_.rx_paused(); }

 private:
  void drop_rx();
  static fw::BoardSeam make_seam(An386Board* self, bool motors);
  static void on_read_encoders(void* ctx, std::int32_t (&counts)[fw::kMotorCount]);
  static void on_motor_output(void* ctx, const float (&duty)[fw::kMotorCount]);
  static void on_output(void* ctx, float value);
  static bool on_send(void* ctx, const protocol::Report& report);
  static void on_log(void* ctx, const char* line);
  static std::uint32_t on_subtick(void* ctx);
  static bool inbox_has_room(void* ctx);
  static void deliver(void* ctx, const protocol::Report& report);

  TickTimer timer_;
  Link link_{kUart0};
  NetLink net_{kEthernet};
  bool net_on_ = false;
  OutputTrace trace_;
  std::uint32_t tick_hz_;
  bool tracing_;
  std::uint32_t inbox_refused_ = 0;  // on_packet said no although the link checked for room (a bug)
  volatile std::uint32_t ticks_ = 0;
  std::uint32_t listen_from_tick_ = 0;
  std::uint32_t rx_lost_ = 0;  // bytes (UART) or frames (Ethernet) dropped before listen_from_tick_
  BenchMotors* motors_ = nullptr;
  fw::Core core_;  // last: its seam points at the members above
};

}  // namespace hmp::board
