#pragma once
// Driver for the CMSDK APB UART (Arm Cortex-M System Design Kit TRM, DDI0479): UART0 of the AN386 at
// 0x40004000, RX interrupt = IRQ 0, TX interrupt = IRQ 1. The peripheral is 8N1 only, with a one-byte
// buffer in each direction (no FIFO):
//   DATA      0x000  read: the received byte (clears STATE.RXFULL); write: the byte to send
//   STATE     0x004  bit 0 TX buffer full, bit 1 RX buffer full, bit 2 TX overrun, bit 3 RX overrun (W1C)
//   CTRL      0x008  bit 0 TX enable, 1 RX enable, 2 TX interrupt, 3 RX interrupt, 4/5 TX/RX overrun interrupt
//   INTSTATUS 0x00C  read: bit 0 TX, 1 RX, 2 TX overrun, 3 RX overrun; write 1 to clear (INTCLEAR)
//   BAUDDIV   0x010  baud = PCLK / BAUDDIV, at least 16
// The TX interrupt is raised when the transmit buffer goes from full to empty, the RX interrupt when a
// byte arrives; both stay raised until cleared in INTCLEAR.
#include <cstdint>

namespace hmp::board {

class CmsdkUart {
 public:
  constexpr CmsdkUart(std::uintptr_t base, unsigned rx_irq, unsigned tx_irq)
      : base_(base), rx_irq_(rx_irq), tx_irq_(tx_irq) {}

  // 8N1 at `baud` (the emulator ignores the rate but wants a valid divider), both directions and their
  // interrupts enabled in the UART. The NVIC side is left to the caller.
  void init(std::uint32_t pclk_hz, std::uint32_t baud) const;

  bool rx_full() const;
  std::uint8_t read() const;  // only meaningful when rx_full()
  bool tx_full() const;
  void write(std::uint8_t byte) const;  // only when !tx_full(), or the byte is lost (TX overrun)
  // Overrun flags (a byte arrived before the last one was read); reading clears them.
  bool take_rx_overrun() const;

  void clear_rx_interrupt() const;
  void clear_tx_interrupt() const;

  // The serial link's flow control (boards/cortex-m/serial_link.hpp), through the NVIC: RX and TX have
  // interrupts of their own here, and a cleared RX interrupt is raised again by hand on resume.
  void pause_rx() const;
  void resume_rx() const;
  void kick_tx() const;
  void tx_idle() const {}  // the TX interrupt is an edge (buffer went empty): nothing to mask

  unsigned rx_irq() const { return rx_irq_; }
  unsigned tx_irq() const { return tx_irq_; }

 private:
  std::uintptr_t base_;
  unsigned rx_irq_, tx_irq_;
};

inline constexpr CmsdkUart kUart0{0x40004000, 0, 1};

}  // namespace hmp::board
