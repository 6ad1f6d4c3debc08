#include "host/transport/handshake.hpp"

#include <algorithm>
#include <chrono>

namespace hmp::transport {

namespace {

using SteadyClock = std::chrono::steady_clock;

Timeout left_until(SteadyClock::time_point deadline) {
  const auto left = std::chrono::duration_cast<Timeout>(deadline - SteadyClock::now());
  return left.count() > 0 ? left : Timeout{0};
}

// Bytes 0–4 of a HelloReply are the same in every protocol version: enough to name a device's version
// even when the rest of its reply does not decode under ours.
std::optional<std::uint16_t> foreign_hello_version(const Report& r) {
  if (r[0] != static_cast<std::uint8_t>(protocol::Type::hello_reply)) return std::nullopt;
  return static_cast<std::uint16_t>(r[3] | (r[4] << 8));
}

}  // namespace

std::optional<DeviceIdentity> say_hello(Transport& link, std::uint16_t seq, Timeout timeout, Timeout resend) {
  Report hello;
  protocol::encode(protocol::make(protocol::Type::hello, seq), hello);
  if (resend.count() <= 0) resend = kHelloResend;

  DeviceIdentity id;
  bool have_hello = false;
  auto deadline = SteadyClock::now() + timeout;
  auto next_hello = SteadyClock::now();
  for (;;) {
    if (!have_hello && SteadyClock::now() >= next_hello) {
      if (!link.send(hello)) return std::nullopt;
      ++id.hellos_sent;
      next_hello = SteadyClock::now() + resend;
    }
    const auto wake = have_hello ? deadline : std::min(deadline, next_hello);
    Report report;
    const Received got = link.receive(report, left_until(wake));
    if (got == Received::closed) break;
    if (got == Received::timeout) {
      if (SteadyClock::now() >= deadline) break;
      continue;
    }
    protocol::Message m;
    if (protocol::decode(report, m) != protocol::ErrorCode::none) {
      if (const auto version = foreign_hello_version(report); version && !have_hello) {
        id.hello = protocol::HelloReply{};
        id.hello.protocol_version = *version;
        return id;  // we cannot read its Status either
      }
      continue;
    }
    if (!have_hello && m.type == protocol::Type::hello_reply) {
      id.hello = m.hello_reply;
      have_hello = true;
      if (!id.compatible()) return id;
      deadline = SteadyClock::now() + timeout;
    } else if (have_hello && m.type == protocol::Type::status) {
      id.status = m.status;
      return id;
    }
  }
  if (!have_hello) return std::nullopt;
  return id;
}

const char* board_name(protocol::Board board) {
  switch (board) {
    case protocol::Board::sim: return "sim";
    case protocol::Board::qemu_an386: return "qemu-an386";
    case protocol::Board::stm32f407: return "stm32f407";
  }
  return "unknown";
}

const char* state_name(protocol::State state) {
  switch (state) {
    case protocol::State::idle: return "idle";
    case protocol::State::playing: return "playing";
    case protocol::State::paused: return "paused";
    case protocol::State::stopped: return "stopped";
    case protocol::State::fault: return "fault";
  }
  return "unknown";
}

namespace {

// "none", or the names of the set bits joined by commas (a bit without a name as "bitN").
template <std::size_t N>
std::string bit_names(std::uint32_t bits, const char* const (&names)[N]) {
  std::string out;
  for (std::uint32_t bit = 0; bit < 32; ++bit) {
    if ((bits >> bit & 1u) == 0) continue;
    if (!out.empty()) out += ',';
    out += bit < N ? names[bit] : "bit" + std::to_string(bit);
  }
  return out.empty() ? "none" : out;
}

}  // namespace

std::string fault_names(std::uint32_t faults) {
  static const char* const kNames[] = {"estop",         "watchdog",      "output_limit", "queue_overflow",
                                       "qp_infeasible", "pose_diverged", "encoder_jump", "string_slack"};
  return bit_names(faults, kNames);
}

std::string board_flag_names(std::uint8_t flags) {
  static const char* const kNames[] = {"clock_fallback", "no_usb", "watchdog_reset", "no_drive"};
  return bit_names(flags, kNames);
}

std::string firmware_version(const protocol::HelloReply& hello) {
  return std::to_string(hello.fw_major) + "." + std::to_string(hello.fw_minor) + "." + std::to_string(hello.fw_patch);
}

}  // namespace hmp::transport
