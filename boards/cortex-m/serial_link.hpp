#pragma once
// The protocol over a UART (design §9: the same 64-byte reports, framed by shared/framing: COBS + CRC-16),
// for any UART driver with the small interface below (boards/qemu-an386/uart.hpp, boards/stm32f407/usart.hpp).
//
// Receive (UART RX interrupt): bytes → framing::Decoder → `deliver` (the core's on_packet). Frames that
// are cut, corrupted or of the wrong size are dropped and counted by the decoder; the core never sees
// them. The link holds the line back instead of losing reports: when the core's inbox is full it stops
// reading the UART (the byte stays in the UART; QEMU then stops delivering, the host's socket buffers)
// and the tick resumes it once there is room (resume_rx()).
//
// Transmit: the core's background (Core::poll, in the main loop) copies each device report into a queue
// of whole reports (queue_report(), a lock-free SPSC ring) and kicks the TX interrupt. The TX interrupt,
// which runs at a lower priority than the tick, frames one report at a time and feeds the UART byte by
// byte. The tick never waits for the line: a full queue drops the report (the core counts it in
// Stats::tx_dropped).
//
// The UART driver provides (all cheap, callable from its interrupts and the main loop):
//   rx_full() read() take_rx_overrun() clear_rx_interrupt()   receive side
//   tx_full() write(byte) clear_tx_interrupt()                 transmit side
//   pause_rx() resume_rx()   stop / restart the RX interrupt (resume re-raises it for a waiting byte)
//   kick_tx()                make the TX interrupt run (main loop, after queueing)
//   tx_idle()                the queue ran dry (a level-triggered "TX empty" interrupt must be masked)
#include <cstdint>

#include "firmware/spsc_queue.hpp"
#include "shared/framing/framing.hpp"
#include "shared/protocol/protocol.hpp"

namespace hmp::board {

// Where a link hands the reports it receives (the board's inbox).
struct LinkSink {
  void* ctx = nullptr;
  bool (*has_room)(void* ctx) = nullptr;                                 // may another report be taken?
  void (*deliver)(void* ctx, const protocol::Report& report) = nullptr;  // one intact report
};

template <typename Uart>
class SerialLink {
 public:
  using Sink = LinkSink;
  struct Counters {
    std::uint32_t rx_bytes = 0;
    std::uint32_t rx_overruns = 0;  // bytes the UART lost (cannot happen in QEMU: it waits for DATA reads)
    std::uint32_t rx_held = 0;      // times reception paused for a full inbox
    std::uint32_t tx_frames = 0;
    std::uint32_t tx_dropped = 0;  // reports the queue had no room for
  };
  static constexpr std::uint32_t kTxQueueReports = 16;  // a tick sends at most ~6 (Status, Started, Errors)

  explicit SerialLink(const Uart& uart) : uart_(uart) {}
  // Before the UART's interrupts are enabled.
  void set_sink(const Sink& sink) { sink_ = sink; }

  // Interrupt handlers (a UART with one interrupt for both directions calls both).
  void on_rx_interrupt() {
    for (;;) {
      // Clear first, then look: a byte that arrives after the look raises the interrupt again.
      uart_.clear_rx_interrupt();
      if (uart_.take_rx_overrun()) {
        ++counters_.rx_overruns;
        decoder_.reset();  // the frame in progress lost a byte; its CRC would fail anyway
      }
      if (!uart_.rx_full()) return;
      if (!sink_.has_room(sink_.ctx)) {
        // Paused first, flagged second: a tick that sees the flag always finds the line paused.
        uart_.pause_rx();
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

  void on_tx_interrupt() {
    for (;;) {
      // Clear first, then look: if the UART is still busy, its "buffer empty" interrupt comes later.
      uart_.clear_tx_interrupt();
      if (frame_pos_ == frame_len_) {
        const QueuedReport* next = tx_queue_.front();
        if (next == nullptr) {
          uart_.tx_idle();
          // A report queued between the look and tx_idle() kicked before the mask: look once more.
          if (tx_queue_.front() == nullptr) return;
          uart_.kick_tx();
          continue;
        }
        std::uint32_t start = 0;
        if (first_frame_) {  // ends whatever the host's decoder may hold from before our reset
          frame_[start++] = 0x00;
          first_frame_ = false;
        }
        frame_len_ = start + static_cast<std::uint32_t>(framing::encode(next->bytes, protocol::wire_size(next->bytes),
                                                                        frame_ + start, framing::kMaxFrame));
        frame_pos_ = 0;
        tx_queue_.pop();
        ++counters_.tx_frames;
      }
      if (uart_.tx_full()) return;
      uart_.write(frame_[frame_pos_++]);
    }
  }

  // Main loop (the core's background context: the queue's only producer).
  bool queue_report(const protocol::Report& report) {
    QueuedReport* slot = tx_queue_.prepare();
    if (slot == nullptr) {
      ++counters_.tx_dropped;
      return false;
    }
    for (std::uint32_t i = 0; i < protocol::kReportSize; ++i) slot->bytes[i] = report[i];
    tx_queue_.commit();
    uart_.kick_tx();
    return true;
  }

  // Call after the core has taken reports from its inbox (the tick).
  void resume_rx() {
    if (!rx_paused_ || !sink_.has_room(sink_.ctx)) return;
    rx_paused_ = false;
    uart_.resume_rx();
  }

  const framing::DecoderCounters& frame_counters() const { return decoder_.counters(); }
  const Counters& counters() const { return counters_; }
  // Read by the main loop: changes with every received byte (the exit-when-idle option watches it).
  std::uint32_t rx_bytes() const { return *static_cast<const volatile std::uint32_t*>(&counters_.rx_bytes); }
  // Reception is held back for a full inbox (bytes are waiting in the UART and behind it).
  bool rx_paused() const { return rx_paused_; }

 private:
  struct QueuedReport {
    protocol::Report bytes;
  };

  const Uart& uart_;
  Sink sink_;
  framing::Decoder decoder_{protocol::kReportSize};
  fw::SpscQueue<QueuedReport, kTxQueueReports> tx_queue_;
  std::uint8_t frame_[framing::kMaxFrame + 1] = {};  // + the delimiter sent before the first frame
  std::uint32_t frame_len_ = 0, frame_pos_ = 0;
  bool first_frame_ = true;
  volatile bool rx_paused_ = false;
  Counters counters_;
};

}  // namespace hmp::board
