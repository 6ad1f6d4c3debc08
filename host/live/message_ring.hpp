#pragma once
// The MIDI messages of one input port on their way from its callback to `hmp live`'s loop: one writer
// (the port's callback, which may be JACK's real-time process thread) and one reader, no lock and no
// allocation on the writer's side. A full ring drops the message and counts it; nothing blocks.
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

namespace hmp::live {

struct MidiChunk {
  std::int64_t received_us = 0;
  std::uint8_t size = 0;  // 1–3
  std::uint8_t bytes[3] = {};
};

class MessageRing {
 public:
  static constexpr std::size_t kCapacity = 8192;  // chunks: 80 ms of a 100,000 message/s flood

  // Writer: a message of any length, as consecutive chunks of up to 3 bytes (a channel message is one),
  // all or none. False (and counted in dropped()) when the ring has no room for it.
  bool push(std::int64_t received_us, const std::uint8_t* bytes, std::size_t n) {
    const std::size_t chunks = (n + 2) / 3;
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (chunks == 0) return true;
    if (tail - head_.load(std::memory_order_acquire) + chunks > kCapacity) {
      dropped_.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    for (std::size_t c = 0; c < chunks; ++c) {
      MidiChunk& slot = slots_[(tail + c) % kCapacity];
      slot.received_us = received_us;
      slot.size = static_cast<std::uint8_t>(n - 3 * c < 3 ? n - 3 * c : 3);
      for (std::uint8_t b = 0; b < slot.size; ++b) slot.bytes[b] = bytes[3 * c + b];
    }
    tail_.store(tail + chunks, std::memory_order_release);
    return true;
  }

  // Reader: calls take(const MidiChunk&) for every chunk written so far, in order.
  template <class Take>
  void drain(Take&& take) {
    std::size_t head = head_.load(std::memory_order_relaxed);
    const std::size_t tail = tail_.load(std::memory_order_acquire);
    for (; head != tail; ++head) take(slots_[head % kCapacity]);
    head_.store(head, std::memory_order_release);
  }

  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }

 private:
  std::array<MidiChunk, kCapacity> slots_{};
  std::atomic<std::size_t> head_{0}, tail_{0};
  std::atomic<std::uint64_t> dropped_{0};
};

}  // namespace hmp::live
