#pragma once
// The host's half of the protocol's session rules (docs/protocol.md, "Sequence numbers and flow control"),
// written once for every host: the player's DeviceLink, `hmp sim` and the firmware tests.
//  - Host reports are numbered 1, 2, …, 0xFFFF, 1, …: 0 never names a report, because Status.last_seq = 0
//    means "nothing processed yet".
//  - Credit: the note reports the device will still accept = queue_free of its newest Status minus the
//    note reports sent after that Status's last_seq (in flight: the device had not seen them yet).
// No I/O, no threads, no clock: callers send the reports and feed back every Status they receive (and
// lock around it if they share it between threads).
#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>

#include "shared/protocol/protocol.hpp"

namespace hmp::transport {

// Wrap-aware "a was sent no later than b" for 16-bit sequence numbers (numbers in flight are close).
constexpr bool seq_not_after(std::uint16_t a, std::uint16_t b) {
  return static_cast<std::int16_t>(static_cast<std::uint16_t>(a - b)) <= 0;
}

constexpr bool is_note_report(protocol::Type t) { return t == protocol::Type::notes || t == protocol::Type::long_note; }

class HostSession {
 public:
  // The number the next report will carry.
  std::uint16_t next_seq() const { return protocol::next_seq(last_sent_); }
  // Numbers `m`, encodes it into `out` and, for a note report, counts it in flight (do this before
  // sending: a quick Status must already see it). Throws std::logic_error for a message encode() refuses
  // (the caller built it wrong).
  std::uint16_t number(protocol::Message& m, protocol::Report& out);
  // The number for a report that is not a note report and that the caller encodes itself (the Hello of
  // transport::say_hello).
  std::uint16_t take_seq() { return last_sent_ = next_seq(); }
  // Takes a Status the device sent: its room, and which reports it has processed.
  void on_status(const protocol::Status& s);
  // A new greeting: the device forgot the old session's notes; numbering goes on.
  void restart(const std::optional<protocol::Status>& first_status);

  // 0 until the first Status.
  int credit() const;
  // The device has processed the report numbered `seq` (its Status.last_seq reached it).
  bool processed(std::uint16_t seq) const;
  const std::optional<protocol::Status>& status() const { return status_; }
  std::uint16_t last_sent() const { return last_sent_; }
  std::size_t in_flight() const { return in_flight_.size(); }

 private:
  std::uint16_t last_sent_ = 0;
  std::optional<protocol::Status> status_;
  std::deque<std::uint16_t> in_flight_;  // note reports not yet covered by a Status.last_seq, oldest first
};

}  // namespace hmp::transport
