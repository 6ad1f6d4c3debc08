#pragma once
// Opening a session (docs/protocol.md, Hello): send Hello, read the HelloReply and the Status the
// device sends right after it. Shared by `hmp devices` and the player.
//
// A board that is still starting (reset by `hmp flash`, a USB-serial adapter plugged in mid-boot, an
// emulator whose UART is not enabled yet) loses what arrives before it listens, so the Hello is sent
// again, with the same sequence number, every kHelloResend until a HelloReply comes or the time is up.
// The device answers every Hello, and a Hello only opens a new session (notes flushed, faults
// acknowledged), so the Hellos still in flight when the first answer arrives change nothing: they reach
// the device before any report the host sends after the handshake, and the HelloReply and Status they
// draw are ordinary late reports to the session that follows.
#include <cstdint>
#include <optional>
#include <string>

#include "host/transport/transport.hpp"

namespace hmp::transport {

struct DeviceIdentity {
  protocol::HelloReply hello;              // for an incompatible device only protocol_version is known
  std::optional<protocol::Status> status;  // absent when the device sent none in time
  int hellos_sent = 0;                     // how many times the Hello went out before the answer
  bool compatible() const { return hello.protocol_version == protocol::kProtocolVersion; }
};

inline constexpr Timeout kHelloResend{100'000};

// Sends a Hello numbered `seq` (again every `resend` while unanswered) and waits up to `timeout` for the
// HelloReply (reports before it are skipped), then up to `timeout` more for the Status. nullopt: no
// HelloReply in time, or the link closed. A HelloReply of another protocol version is recognised by its
// fixed first bytes and returned as such.
std::optional<DeviceIdentity> say_hello(Transport& link, std::uint16_t seq, Timeout timeout,
                                        Timeout resend = kHelloResend);

const char* board_name(protocol::Board board);     // "sim", "qemu-an386", "stm32f407" (HMP_BOARD names)
const char* state_name(protocol::State state);     // "idle", "playing", …
std::string fault_names(std::uint32_t faults);     // "none" or "estop,watchdog"
std::string board_flag_names(std::uint8_t flags);  // "none" or "clock_fallback,no_usb" (protocol::BoardFlag)
std::string firmware_version(const protocol::HelloReply& hello);  // "0.1.0"

}  // namespace hmp::transport
