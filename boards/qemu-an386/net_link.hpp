#pragma once
// The protocol over the AN386's Ethernet controller (shared/framing/ether_frame.hpp: one report per
// frame), the QEMU board's alternative to its UART: `link=net` on the image's command line, `--device
// qemu:net` on the host's. Same contract as boards/cortex-m/serial_link.hpp: received reports go to the
// sink from the controller's interrupt; when the sink is full, reception pauses (frames wait in the
// controller's FIFO) until the tick resumes it; the main loop sends, and a full TX FIFO drops the report
// (counted) instead of waiting.
#include <cstdint>

#include "boards/cortex-m/cortex_m.hpp"
#include "boards/cortex-m/serial_link.hpp"
#include "lan9118.hpp"
#include "shared/framing/ether_frame.hpp"
#include "shared/protocol/protocol.hpp"

namespace hmp::board {

class NetLink {
 public:
  struct Counters {
    std::uint32_t rx_frames = 0;
    std::uint32_t rx_foreign = 0;  // frames that are not ours (another EtherType or size): dropped
    std::uint32_t rx_held = 0;     // times reception paused for a full inbox
    std::uint32_t tx_frames = 0;
    std::uint32_t tx_dropped = 0;  // reports the TX FIFO had no room for
  };

  explicit NetLink(const Lan9118& nic) : nic_(nic) {}
  void set_sink(const LinkSink& sink) { sink_ = sink; }
  // The controller on; false when there is none. Its interrupt is the caller's to enable.
  bool start() const { return nic_.init(); }

  void on_interrupt() {
    nic_.clear_rx_interrupt();  // clear first, then look: a frame arriving after the look raises it again
    while (nic_.frames_waiting() != 0) {
      if (!sink_.has_room(sink_.ctx)) {
        nvic::disable(nic_.irq());  // paused first, flagged second: a tick that sees the flag finds it paused
        rx_paused_ = true;
        ++counters_.rx_held;
        return;
      }
      std::uint8_t frame[framing::ether::kFrameBytes];
      const std::size_t size = nic_.read_frame(frame, sizeof frame);
      ++counters_.rx_frames;
      const std::uint8_t* report = framing::ether::payload_of(frame, size);
      if (report == nullptr) {
        ++counters_.rx_foreign;
        continue;
      }
      sink_.deliver(sink_.ctx, *reinterpret_cast<const protocol::Report*>(report));
    }
  }

  // Takes and drops every waiting frame (a board still starting up); returns how many.
  std::uint32_t drop_received() const {
    nic_.clear_rx_interrupt();
    std::uint32_t n = 0;
    std::uint8_t frame[framing::ether::kFrameBytes];
    for (; nic_.frames_waiting() != 0; ++n) nic_.read_frame(frame, sizeof frame);
    return n;
  }

  // Main loop (the only sender).
  bool queue_report(const protocol::Report& report) {
    if (!nic_.tx_room(framing::ether::kFrameBytes)) {
      ++counters_.tx_dropped;
      return false;
    }
    std::uint8_t frame[framing::ether::kFrameBytes];
    framing::ether::build(report, framing::ether::kDeviceMac, framing::ether::kHostMac, frame);
    nic_.send(frame, sizeof frame);
    ++counters_.tx_frames;
    return true;
  }

  // The tick, after the core has taken reports from its inbox.
  void resume_rx() {
    if (!rx_paused_ || !sink_.has_room(sink_.ctx)) return;
    rx_paused_ = false;
    nvic::enable(nic_.irq());
    nvic::set_pending(nic_.irq());  // the waiting frames' interrupt was cleared
  }

  // Read by the main loop: changes with every received frame (the exit-when-idle option watches it).
  std::uint32_t rx_count() const { return *static_cast<const volatile std::uint32_t*>(&counters_.rx_frames); }
  bool rx_paused() const { return rx_paused_; }
  const Counters& counters() const { return counters_; }

 private:
  const Lan9118& nic_;
  LinkSink sink_;
  volatile bool rx_paused_ = false;
  Counters counters_;
};

}  // namespace hmp::board
