#include "serial_link.hpp"

#include "registers.hpp"

namespace hmp::board {
namespace {

// Lower than the tick (SysTick gets 0): the UART never delays the tick, and a report's arrival tick is
// read consistently (the tick cannot be half-way through when the UART interrupt runs).
constexpr std::uint8_t kUartPriority = 0x80;

}  // namespace

void SerialLink::start(const Sink& sink) {
  sink_ = sink;
  uart_.init(kCoreHz, 115200);
  nvic::set_priority(uart_.rx_irq(), kUartPriority);
  nvic::set_priority(uart_.tx_irq(), kUartPriority);
  nvic::enable(uart_.rx_irq());
  nvic::enable(uart_.tx_irq());
}

void SerialLink::on_rx_interrupt() {
  for (;;) {
    // Clear first, then look: a byte that arrives after the look raises the interrupt again.
    uart_.clear_rx_interrupt();
    if (uart_.take_rx_overrun()) {
      ++counters_.rx_overruns;
      decoder_.reset();  // the frame in progress lost a byte; its CRC would fail anyway
    }
    if (!uart_.rx_full()) return;
    if (!sink_.has_room(sink_.ctx)) {
      // Masked first, flagged second: a tick that sees the flag always finds the line masked.
      nvic::disable(uart_.rx_irq());
      rx_paused_ = true;
      ++counters_.rx_held;
      return;
    }
    const std::uint8_t byte = uart_.read();
    ++counters_.rx_bytes;
    if (decoder_.push(byte)) {
      sink_.deliver(sink_.ctx, *reinterpret_cast<const protocol::Report*>(decoder_.packet()));
    }
  }
}

void SerialLink::resume_rx() {
  if (!rx_paused_ || !sink_.has_room(sink_.ctx)) return;
  rx_paused_ = false;
  nvic::enable(uart_.rx_irq());
  // The waiting byte's interrupt was already cleared: raise it again so the handler reads it.
  nvic::set_pending(uart_.rx_irq());
}

bool SerialLink::queue_report(const protocol::Report& report) {
  QueuedReport* slot = tx_queue_.prepare();
  if (slot == nullptr) {
    ++counters_.tx_dropped;
    return false;
  }
  for (std::uint32_t i = 0; i < protocol::kReportSize; ++i) slot->bytes[i] = report[i];
  tx_queue_.commit();
  nvic::set_pending(uart_.tx_irq());
  return true;
}

void SerialLink::on_tx_interrupt() {
  for (;;) {
    // Clear first, then look: if the UART is still busy, its "buffer empty" interrupt comes later.
    uart_.clear_tx_interrupt();
    if (frame_pos_ == frame_len_) {
      const QueuedReport* next = tx_queue_.front();
      if (next == nullptr) return;
      std::uint32_t start = 0;
      if (first_frame_) {  // ends whatever the host's decoder may hold from before our reset
        frame_[start++] = 0x00;
        first_frame_ = false;
      }
      frame_len_ = start + static_cast<std::uint32_t>(
                               framing::encode(next->bytes, protocol::kReportSize, frame_ + start, framing::kMaxFrame));
      frame_pos_ = 0;
      tx_queue_.pop();
      ++counters_.tx_frames;
    }
    if (uart_.tx_full()) return;
    uart_.write(frame_[frame_pos_++]);
  }
}

}  // namespace hmp::board
