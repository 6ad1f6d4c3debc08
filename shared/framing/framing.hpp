#pragma once
// Serial framing for UART links (design §9: the same 64-byte reports over every transport).
//
// frame = COBS(packet ‖ crc16) ‖ 0x00
//   crc16: CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, not reflected, no final xor) over the packet,
//          appended little-endian like every other field of the protocol.
//   COBS:  consistent-overhead byte stuffing, so 0x00 appears only as the frame delimiter and a receiver
//          that starts listening mid-stream (or loses bytes) resynchronises at the next 0x00.
//
// The decoder is a byte-at-a-time state machine with a fixed buffer: it never holds more than
// kMaxPacket + 2 bytes, drops every frame it cannot prove intact (bad COBS structure, CRC mismatch,
// oversized, cut short, wrong length) and only counts them. Two 0x00 in a row (an empty frame) are
// idle filler, not an error: a sender may put a 0x00 before a frame to end whatever a reset left behind.
#include <cstddef>
#include <cstdint>

namespace hmp::framing {

inline constexpr std::size_t kMaxPacket = 64;  // one protocol report
inline constexpr std::size_t kCrcBytes = 2;

// Largest frame for an n-byte packet: one COBS code byte per started run of 254 bytes, plus the delimiter.
constexpr std::size_t max_frame_size(std::size_t packet_size) {
  const std::size_t stuffed = packet_size + kCrcBytes;
  return stuffed + stuffed / 254 + 1 + 1;
}
inline constexpr std::size_t kMaxFrame = max_frame_size(kMaxPacket);

// The bytes of `packet` a frame needs to carry: all but its trailing zeros, at least one. A receiver
// with an expected size puts the zeros back; a protocol report is mostly padding (a Live report with
// one event: 68 bytes framed whole, 18 so), and on a serial link every byte costs time.
constexpr std::size_t carried_size(const std::uint8_t* packet, std::size_t size) {
  while (size > 1 && packet[size - 1] == 0) --size;
  return size;
}

std::uint16_t crc16_ccitt_false(const std::uint8_t* data, std::size_t size, std::uint16_t crc = 0xFFFF);

// Writes the frame for `packet` into `out` and returns its length (delimiter included), or 0 when the
// packet is longer than kMaxPacket or `capacity` < max_frame_size(size) (nothing useful is written then).
std::size_t encode(const std::uint8_t* packet, std::size_t size, std::uint8_t* out, std::size_t capacity);

struct DecoderCounters {
  std::uint32_t packets = 0;     // frames delivered
  std::uint32_t crc_errors = 0;  // well-formed COBS, CRC mismatch
  std::uint32_t malformed = 0;   // COBS block runs past the delimiter, or fewer bytes than a CRC (cut frames)
  std::uint32_t oversized = 0;   // more than kMaxPacket + 2 decoded bytes before the delimiter
  std::uint32_t wrong_size = 0;  // intact frame with an empty packet, or longer than the expected size
  std::uint32_t dropped() const { return crc_errors + malformed + oversized + wrong_size; }
};

class Decoder {
 public:
  // expected_size: the size of every packet delivered (protocol links: kMaxPacket); a frame may carry
  // 1 … expected_size bytes, the rest are zeros the sender left out (carried_size), put back here.
  // 0 delivers packets of 0 … kMaxPacket bytes as they came.
  // A size beyond kMaxPacket is kMaxPacket: buf_ holds no more.
  explicit Decoder(std::size_t expected_size = kMaxPacket)
      : expected_(expected_size < kMaxPacket ? expected_size : kMaxPacket) {}

  // Feeds one received byte. Returns true when it was the delimiter of an intact frame: packet() and
  // size() then hold the packet (zero-filled to the expected size) until the next push().
  bool push(std::uint8_t byte);

  const std::uint8_t* packet() const { return buf_; }
  std::size_t size() const { return packet_size_; }
  const DecoderCounters& counters() const { return counters_; }
  // Forget a partly received frame (e.g. after a UART overrun); counts nothing.
  void reset();

 private:
  bool finish_frame();  // at a delimiter: checks and delivers or counts
  void append(std::uint8_t b);

  std::uint8_t buf_[kMaxPacket + kCrcBytes] = {};
  std::size_t len_ = 0;
  std::size_t packet_size_ = 0;
  std::size_t expected_ = kMaxPacket;
  std::uint8_t block_left_ = 0;  // data bytes still due in the current COBS block (0: next is a code)
  bool zero_pending_ = false;    // the block just finished stands for a 0x00 unless the frame ends here
  bool overflowed_ = false;      // this frame already exceeded the buffer: skip to the delimiter
  bool in_frame_ = false;        // at least one byte since the last delimiter
  DecoderCounters counters_;
};

}  // namespace hmp::framing
