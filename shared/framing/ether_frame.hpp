#pragma once
// Reports over Ethernet (design §9), the QEMU board's network link: each 64-byte report travels whole in
// one frame, so a report costs the emulator one packet instead of one round trip per byte as on its
// one-byte UART.
//
// frame = destination MAC (6) ‖ source MAC (6) ‖ EtherType 0x88B5 (2, big-endian) ‖ the report (64)
//   0x88B5: IEEE 802's "local experimental" EtherType, for protocols that never leave a private link.
//   MACs: locally administered (bit 1 of the first byte set), "HMP" in the middle; the link is
//   point-to-point, so receivers do not check them.
// The integrity check is the network's (the Ethernet FCS); a frame of another type or size is dropped.
#include <cstddef>
#include <cstdint>

namespace hmp::framing::ether {

inline constexpr std::size_t kHeaderBytes = 14;
inline constexpr std::size_t kPayloadBytes = 64;  // one protocol report
inline constexpr std::size_t kFrameBytes = kHeaderBytes + kPayloadBytes;
inline constexpr std::uint16_t kEtherType = 0x88B5;
inline constexpr std::uint8_t kDeviceMac[6] = {0x02, 'H', 'M', 'P', 0x00, 0x01};
inline constexpr std::uint8_t kHostMac[6] = {0x02, 'H', 'M', 'P', 0x00, 0x02};

// Writes the frame carrying `payload` (kPayloadBytes) from `source` to `destination` into `out`
// (kFrameBytes).
constexpr void build(const std::uint8_t* payload, const std::uint8_t (&source)[6], const std::uint8_t (&destination)[6],
                     std::uint8_t* out) {
  for (std::size_t i = 0; i < 6; ++i) {
    out[i] = destination[i];
    out[6 + i] = source[i];
  }
  out[12] = static_cast<std::uint8_t>(kEtherType >> 8);
  out[13] = static_cast<std::uint8_t>(kEtherType & 0xFF);
  for (std::size_t i = 0; i < kPayloadBytes; ++i) out[kHeaderBytes + i] = payload[i];
}

// The report a received frame carries, or nullptr when it is not one of ours: another EtherType, or
// not exactly kFrameBytes long (`size` without the FCS).
constexpr const std::uint8_t* payload_of(const std::uint8_t* frame, std::size_t size) {
  if (size != kFrameBytes) return nullptr;
  if (frame[12] != (kEtherType >> 8) || frame[13] != (kEtherType & 0xFF)) return nullptr;
  return frame + kHeaderBytes;
}

}  // namespace hmp::framing::ether
