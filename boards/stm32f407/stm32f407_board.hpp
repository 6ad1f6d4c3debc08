#pragma once
// The stm32f407 board: the firmware core (firmware/core.hpp) on SysTick, with the SPIDAR's motors and
// encoders, the emergency-stop input, the watchdog and the USART2 link. Fills in the BoardSeam; main()
// and the interrupt handlers (startup.cpp's vector table) call in here.
//
// Priorities (lower number = more urgent): the software encoders' pin interrupts 0x00 (an edge must be
// taken before the next), the emergency stop 0x00, the tick 0x40, USART2 and USB 0x80. The main loop
// (thread mode) runs the core's background work, feeds the watchdog and sleeps in `wfi`.
//
// Two links to the host: USB HID when the controller started, USART2 always. Reports from either reach
// the core; the core's reports go to USB while the host has it configured, else to the UART.
#include <cstdint>

#include "boards/cortex-m/serial_link.hpp"
#include "boards/cortex-m/systick_timer.hpp"
#include "clocks.hpp"
#include "encoders.hpp"
#include "firmware/core.hpp"
#include "firmware/usb/device.hpp"
#include "motors.hpp"
#include "usart.hpp"
#include "usb_controller.hpp"

namespace hmp::board::stm32 {

class Stm32Board {
 public:
  using Link = SerialLink<Usart2>;
  static constexpr std::uint32_t kUartBaud = 460'800;

  // `usb`: the started USB controller, or null (no USB: the UART only).
  Stm32Board(const Clocks& clocks, std::uint8_t board_flags, UsbController* usb);
  Stm32Board(const Stm32Board&) = delete;
  Stm32Board& operator=(const Stm32Board&) = delete;

  void start();  // link, estop, encoders, tick; motors enabled when the estop allows

  // Interrupt handlers.
  void on_tick();
  void on_usart() {
    link_.on_rx_interrupt();
    link_.on_tx_interrupt();
  }
  void on_estop_edge();
  void on_usb() { usb_controller_->on_interrupt(); }
  void on_encoder_edge(int encoder) { encoders_.on_pin_edge(encoder); }

  // Main loop: the core's background work; true if there was any.
  bool poll();
  std::uint32_t ticks() const { return ticks_; }
  void show_state();  // LEDs

  fw::Core& core() { return core_; }

 private:
  static fw::BoardSeam make_seam(Stm32Board* self, const Clocks& clocks, std::uint8_t flags);
  static void on_read_encoders(void* ctx, std::int32_t (&counts)[fw::kMotorCount]);
  static void on_motor_output(void* ctx, const float (&duty)[fw::kMotorCount]);
  static bool on_send(void* ctx, const protocol::Report& report);
  static std::uint32_t on_subtick(void* ctx);
  static bool inbox_has_room(void* ctx);
  static void deliver(void* ctx, const protocol::Report& report);
  bool estop_input_active() const;
  bool motors_allowed() const;

  Clocks clocks_;
  TickTimer timer_;
  Link link_{kUsart2};
  Motors motors_;
  Encoders encoders_;
  volatile std::uint32_t ticks_ = 0;
  UsbController* usb_controller_;
  char serial_[25] = {};
  fw::Core core_;  // after what its seam points at
  fw::usb::Device usb_;
};

}  // namespace hmp::board::stm32
