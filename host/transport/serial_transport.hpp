#pragma once
// Serial link (design §9, §14): each 64-byte report travels as one frame of shared/framing (COBS +
// CRC-16, 0x00 delimiter). The same class serves
//   - a UART board's tty (/dev/ttyACM0, /dev/ttyUSB0): opened raw, 8N1, no flow control, optional speed;
//   - a pty, as QEMU's `-serial pty` gives ("char device redirected to /dev/pts/N" on its stderr);
//   - a unix-domain stream socket path, as QEMU's `-chardev socket,id=c,path=P,server=on,wait=off
//     -serial chardev:c` gives (no pty parsing, no terminal settings: what a launcher that starts
//     qemu-system-arm itself will prefer);
//   - an already connected descriptor (adopt(): a pty master, one end of a socketpair).
// The reader resynchronises at every 0x00 and drops (and counts) every frame it cannot prove intact:
// line noise, a reset mid-frame and boot messages of the firmware cost only the frames they touch.
#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "host/transport/link_state.hpp"
#include "host/transport/report_inbox.hpp"
#include "host/transport/transport.hpp"
#include "shared/framing/framing.hpp"

namespace hmp::transport {

class SerialTransport final : public TransportWithState {
 public:
  struct Options {
    unsigned baud = 0;  // ttys of real UARTs: line speed (9600 … 4000000); 0 keeps the current speed
    // A link that takes no byte for this long is declared dead (send() returns false): a peer that is
    // stopped (QEMU paused, board hung) must not block the player forever.
    Timeout write_timeout = std::chrono::seconds(2);
  };

  // Opens a tty/pty or connects to a unix-domain socket. Throws TransportError with a one-line message.
  static std::unique_ptr<SerialTransport> open(const std::string& path, const Options& options);
  static std::unique_ptr<SerialTransport> open(const std::string& path) { return open(path, Options{}); }
  // Takes ownership of a connected descriptor (made non-blocking; a tty is switched to raw mode).
  static std::unique_ptr<SerialTransport> adopt(int fd, const std::string& name, const Options& options);
  static std::unique_ptr<SerialTransport> adopt(int fd, const std::string& name) { return adopt(fd, name, Options{}); }
  ~SerialTransport() override;

  bool send(const Report& report) override;
  Received receive(Report& out, Timeout timeout) override;
  std::string name() const override { return name_; }
  void close() override;
  // The frame decoder's counters (intact packets, CRC errors, malformed, oversized, wrong size).
  framing::DecoderCounters frame_counters() const;

 private:
  SerialTransport(int fd, std::string name, const Options& options);
  enum class ReadResult { data, would_block, closed };
  ReadResult read_available();
  bool write_all(const std::uint8_t* data, std::size_t size);
  // Waits for `events` on the link or a wake-up by close(); false when the deadline passed first.
  bool wait(short events, std::chrono::steady_clock::time_point deadline);

  int fd_ = -1;
  int wake_fd_ = -1;  // eventfd written by close(): wakes a receive()/send() blocked in ppoll
  bool is_socket_ = false;
  bool resync_ = true;  // send thread: put a 0x00 before the next frame (first frame, after a failed write)
  std::string name_;
  Options options_;
  framing::Decoder decoder_{protocol::kReportSize};  // receive thread only
  ReportInbox inbox_;                                // receive thread only
  mutable std::mutex counters_mutex_;
  framing::DecoderCounters frame_counters_;  // copy of decoder_'s, for other threads
};

}  // namespace hmp::transport
