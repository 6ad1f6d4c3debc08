#pragma once
// The protocol over UART0 (SPEC §9: the same 64-byte reports, framed by shared/framing: COBS + CRC-16).
//
// Receive (UART RX interrupt): bytes → framing::Decoder → `deliver` (the core's on_packet). Frames that
// are cut, corrupted or of the wrong size are dropped and counted by the decoder; the core never sees
// them. The link holds the line back instead of losing reports: when the core's inbox is full it stops
// reading the UART (the byte stays in the UART, QEMU then stops delivering, the host's socket buffers)
// and the tick resumes it once there is room (resume_rx()).
//
// Transmit: the core's background (Core::poll, in the main loop) copies each device report into a queue
// of whole reports (queue_report(), a lock-free SPSC ring) and pends the TX interrupt. The TX interrupt, which runs at a lower priority
// than the tick, frames one report at a time and feeds the UART byte by byte. The tick never waits for
// the line: a full queue drops the report (the core counts it in Stats::tx_dropped).
#include <cstdint>

#include "firmware/spsc_queue.hpp"
#include "shared/framing/framing.hpp"
#include "shared/protocol/protocol.hpp"
#include "uart.hpp"

namespace hmp::board {

class SerialLink {
 public:
  struct Sink {
    void* ctx = nullptr;
    bool (*has_room)(void* ctx) = nullptr;                             // may another report be taken?
    void (*deliver)(void* ctx, const protocol::Report& report) = nullptr;  // one intact report
  };
  struct Counters {
    std::uint32_t rx_bytes = 0;
    std::uint32_t rx_overruns = 0;  // bytes the UART lost (cannot happen in QEMU: it waits for DATA reads)
    std::uint32_t rx_held = 0;      // times reception paused for a full inbox
    std::uint32_t tx_frames = 0;
    std::uint32_t tx_dropped = 0;   // reports the queue had no room for
  };
  static constexpr std::uint32_t kTxQueueReports = 16;  // a tick sends at most ~6 (Status, Started, Errors)

  explicit SerialLink(const CmsdkUart& uart) : uart_(uart) {}
  void start(const Sink& sink);  // UART on, its interrupts enabled below the tick's priority

  // Interrupt handlers (UART0 RX and TX).
  void on_rx_interrupt();
  void on_tx_interrupt();

  // Main loop (the core's background context: the queue's only producer).
  bool queue_report(const protocol::Report& report);
  void resume_rx();  // call after the core has taken reports from its inbox

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

  const CmsdkUart& uart_;
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
