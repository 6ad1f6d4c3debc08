#pragma once
// One interface for every link that carries the protocol's 64-byte reports (design §9, §14): USB HID, a
// framed serial line (UART board, QEMU), the in-process simulated device, and an in-memory loopback
// for tests. The transport moves opaque reports; encoding and decoding are protocol::encode/decode.
//
// Threading: one thread may sit in receive() while another calls send(); close() may be called from
// any thread and wakes a blocked receive() promptly. Two threads must not call receive() (or send())
// at the same time.
#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "shared/protocol/protocol.hpp"

namespace hmp::transport {

using protocol::Report;
using Timeout = std::chrono::microseconds;

// What receive() got.
enum class Received {
  report,   // `out` holds one device report
  timeout,  // nothing arrived in time; the link is still up
  closed,   // the link is gone (peer closed, device unplugged, close() called) and no report is left
};
const char* name(Received r);

// Opening a link failed (no such device, permission, bad path). The message is one line, for the user.
class TransportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Per-link statistics, cumulative since the link was opened.
struct LinkCounters {
  std::uint64_t sent = 0;      // reports handed to the link
  std::uint64_t received = 0;  // reports delivered by receive()
  std::uint64_t dropped = 0;   // incoming data thrown away: bad frames (serial), short reads (HID)
};

class Transport {
 public:
  virtual ~Transport() = default;
  Transport() = default;
  Transport(const Transport&) = delete;
  Transport& operator=(const Transport&) = delete;

  // Sends one report. Blocks while the link applies back-pressure (bounded by the link's own
  // timeout). false: the link is closed (or just died); the report was not delivered and closed_reason()
  // says why.
  virtual bool send(const Report& report) = 0;
  // Waits up to `timeout` (zero: just polls) for one device report. Reports already received are
  // delivered before a closed link is reported.
  virtual Received receive(Report& out, Timeout timeout) = 0;
  // Human-readable link name for messages: "hid:/dev/hidraw3", "serial:/dev/pts/5", "sim", …
  virtual std::string name() const = 0;
  // Closes the link; idempotent. Afterwards send() returns false and receive() returns closed.
  virtual void close() = 0;
  virtual bool is_open() const = 0;
  // Empty while open; otherwise why the link closed ("closed by the host", "peer closed", an OS error).
  virtual std::string closed_reason() const = 0;
  virtual LinkCounters counters() const = 0;
};

}  // namespace hmp::transport
