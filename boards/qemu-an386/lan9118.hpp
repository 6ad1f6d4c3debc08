#pragma once
// Driver for the SMSC LAN9118 Ethernet controller (datasheet: SMSC LAN9118, rev. 1.5), the AN386's
// network interface at 0x40200000, interrupt IRQ 13 (QEMU models it; on the FPGA board it is a LAN9220,
// software compatible). 32-bit register access only. Used in the simplest way: no DMA, every frame
// moved through the FIFO ports word by word, little-endian.
//   RX_DATA_FIFO   0x00  read: the next word of the frame at the head of the RX FIFO
//   TX_DATA_FIFO   0x20  write: TX command A, TX command B, then the frame's words
//   RX_STATUS_FIFO 0x40  read: pops the status of the next frame, bits 29:16 its length with the FCS
//   ID_REV 0x50, IRQ_CFG 0x54 (bit 8 IRQ_EN, 4 IRQ_POL high, 0 IRQ_TYPE push-pull), INT_STS 0x58 (write 1
//   to clear), INT_EN 0x5C (bit 3 RSFL: RX status FIFO above its level), BYTE_TEST 0x64 (reads 0x87654321),
//   TX_CFG 0x70 (bit 1 TX_ON), HW_CFG 0x74 (bit 0 soft reset, self-clearing), RX_FIFO_INF 0x7C (bits
//   23:16 statuses waiting), TX_FIFO_INF 0x80 (bits 15:0 free data bytes), MAC_CSR_CMD 0xA4 (bit 31 busy,
//   bit 30 read, bits 7:0 the MAC register) and MAC_CSR_DATA 0xA8: the MAC's own registers, through which
//   MAC_CR (1) turns the receiver (bit 2) and transmitter (bit 3) on.
#include <cstddef>
#include <cstdint>

namespace hmp::board {

class Lan9118 {
 public:
  constexpr Lan9118(std::uintptr_t base, unsigned irq) : base_(base), irq_(irq) {}

  // Soft reset, then receiver and transmitter on (promiscuous: the link is point to point), the
  // interrupt raised (active high) while a received frame waits. false when no LAN9118 answers.
  bool init() const;

  std::uint32_t frames_waiting() const;  // received frames whose status has not been popped
  // Takes the next received frame out of the RX FIFO (all of its words) and returns its length without
  // the FCS; its first `capacity` bytes are in `out`.
  std::size_t read_frame(std::uint8_t* out, std::size_t capacity) const;
  void clear_rx_interrupt() const;

  // Room for a frame of `size` bytes and its two command words in the TX FIFO.
  bool tx_room(std::size_t size) const;
  // Queues one whole frame (call tx_room first): the controller sends it on its own.
  void send(const std::uint8_t* frame, std::size_t size) const;

  unsigned irq() const { return irq_; }

 private:
  std::uintptr_t base_;
  unsigned irq_;
};

inline constexpr Lan9118 kEthernet{0x40200000, 13};

}  // namespace hmp::board
