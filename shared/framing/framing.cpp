#include "shared/framing/framing.hpp"

namespace hmp::framing {

std::uint16_t crc16_ccitt_false(const std::uint8_t* data, std::size_t size, std::uint16_t crc) {
  for (std::size_t i = 0; i < size; ++i) {
    crc = static_cast<std::uint16_t>(crc ^ (static_cast<std::uint16_t>(data[i]) << 8));
    for (int bit = 0; bit < 8; ++bit) {
      const bool top = (crc & 0x8000u) != 0;
      crc = static_cast<std::uint16_t>(crc << 1);
      if (top) crc = static_cast<std::uint16_t>(crc ^ 0x1021u);
    }
  }
  return crc;
}

std::size_t encode(const std::uint8_t* packet, std::size_t size, std::uint8_t* out, std::size_t capacity) {
  if (size > kMaxPacket || capacity < max_frame_size(size)) return 0;
  const std::uint16_t crc = crc16_ccitt_false(packet, size);
  const std::uint8_t tail[kCrcBytes] = {static_cast<std::uint8_t>(crc), static_cast<std::uint8_t>(crc >> 8)};

  // Classic COBS: each block starts with a code byte = 1 + its count of non-zero bytes; a code below
  // 0xFF also stands for the 0x00 that ended the block (except after the last block).
  std::size_t code_at = 0;
  std::size_t pos = 1;
  std::uint8_t code = 1;
  for (std::size_t i = 0; i < size + kCrcBytes; ++i) {
    const std::uint8_t b = i < size ? packet[i] : tail[i - size];
    if (b == 0) {
      out[code_at] = code;
      code_at = pos++;
      code = 1;
      continue;
    }
    out[pos++] = b;
    if (++code == 0xFF) {  // a full run of 254 bytes: close the block, no zero implied
      out[code_at] = code;
      code_at = pos++;
      code = 1;
    }
  }
  out[code_at] = code;
  out[pos++] = 0x00;
  return pos;
}

void Decoder::reset() {
  len_ = 0;
  block_left_ = 0;
  zero_pending_ = false;
  overflowed_ = false;
  in_frame_ = false;
}

void Decoder::append(std::uint8_t b) {
  if (len_ == sizeof buf_) {
    overflowed_ = true;
    return;
  }
  buf_[len_++] = b;
}

bool Decoder::push(std::uint8_t byte) {
  if (byte == 0x00) {
    const bool delivered = in_frame_ && finish_frame();
    reset();
    return delivered;
  }
  in_frame_ = true;
  if (overflowed_) return false;
  if (block_left_ == 0) {  // a code byte opens the next block
    if (zero_pending_) append(0x00);
    block_left_ = static_cast<std::uint8_t>(byte - 1);
    zero_pending_ = byte != 0xFF;
  } else {
    append(byte);
    --block_left_;
  }
  return false;
}

bool Decoder::finish_frame() {
  if (overflowed_) {
    ++counters_.oversized;
    return false;
  }
  // A block that promised more bytes than arrived, or too few bytes to hold a CRC: the frame was cut.
  if (block_left_ != 0 || len_ < kCrcBytes) {
    ++counters_.malformed;
    return false;
  }
  const std::size_t size = len_ - kCrcBytes;
  const auto received = static_cast<std::uint16_t>(buf_[size] | (buf_[size + 1] << 8));
  if (crc16_ccitt_false(buf_, size) != received) {
    ++counters_.crc_errors;
    return false;
  }
  if (expected_ != 0 && (size == 0 || size > expected_)) {
    ++counters_.wrong_size;
    return false;
  }
  // The zeros the sender left out (and over the CRC bytes, which are no longer needed).
  for (std::size_t i = size; i < expected_; ++i) buf_[i] = 0;
  ++counters_.packets;
  packet_size_ = expected_ != 0 ? expected_ : size;
  return true;
}

}  // namespace hmp::framing
