#pragma once
// USART2 (RM0090 §30) as the serial link's UART (boards/cortex-m/serial_link.hpp): 8N1, one interrupt
// for both directions. "Data register empty" (TXE) is a level, so its interrupt is enabled only while
// the link has bytes to send; pausing reception masks RXNE's interrupt and leaves the byte in DR (the
// sender's side then holds the rest; QEMU's model stops delivering). CR1's interrupt enables are
// written through bit-band aliases: the main loop (kick_tx) and the interrupt (pause_rx, tx_idle) both
// change them, and a read-modify-write from one could undo the other's.
#include <cstdint>

#include "registers.hpp"

namespace hmp::board::stm32 {

class Usart2 {
 public:
  // 8N1 at `baud` from the APB1 clock; receiver, transmitter and the RX interrupt on (NVIC left to the caller).
  void init(std::uint32_t pclk_hz, std::uint32_t baud) const;

  bool rx_full() const { return (reg(usart2::kSr) & usart2::kSrRxne) != 0; }
  std::uint8_t read() const { return static_cast<std::uint8_t>(reg(usart2::kDr)); }
  // A byte was lost. ORE clears on the SR read here followed by the DR read of the byte still waiting
  // (RXNE is set with it), which read() does: the good byte is not thrown away to clear the flag.
  bool take_rx_overrun() const { return (reg(usart2::kSr) & usart2::kSrOre) != 0; }
  void clear_rx_interrupt() const {}  // RXNE clears itself when DR is read
  bool tx_full() const { return (reg(usart2::kSr) & usart2::kSrTxe) == 0; }
  void write(std::uint8_t byte) const { reg(usart2::kDr) = byte; }
  void clear_tx_interrupt() const {}  // TXE clears itself when DR is written

  void pause_rx() const { bitband(usart2::kCr1, usart2::kCr1Rxneie) = 0; }
  void resume_rx() const { bitband(usart2::kCr1, usart2::kCr1Rxneie) = 1; }  // RXNE still set: fires again
  // TXEIE, and the interrupt pended by hand: the silicon would raise it from TXE alone, but QEMU 7.2's
  // model never raises it for TXE; the pended handler then sends while TXE is set (always, there).
  void kick_tx() const {
    bitband(usart2::kCr1, usart2::kCr1Txeie) = 1;
    nvic::set_pending(usart2::kIrq);
  }
  void tx_idle() const { bitband(usart2::kCr1, usart2::kCr1Txeie) = 0; }
};

inline constexpr Usart2 kUsart2{};

}  // namespace hmp::board::stm32
