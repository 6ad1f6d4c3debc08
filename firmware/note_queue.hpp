#pragma once
// The bounded note schedule: notes waiting for their start tick, earliest first (design §8).
// A binary min-heap in a fixed array: push and pop cost O(log n) with n ≤ kCapacity, no allocation.
// Notes with the same start tick leave in arrival order (a chord keeps the order the host sent it in,
// which decides stealing and the `latest` policy exactly as if the host had started them itself).
#include <cstdint>

#include "shared/synth/voice.hpp"

namespace hmp::fw {

struct QueuedNote {
  synth::Note note;
  std::uint32_t arrival = 0;  // tie-break for equal start ticks (wrap-safe comparison)
  std::uint16_t seq = 0;      // report that carried it, and its index there (for Started reports)
  std::uint8_t index = 0;
};

class NoteQueue {
 public:
  static constexpr std::uint16_t kCapacity = 256;

  std::uint16_t size() const { return size_; }
  std::uint16_t free_slots() const { return static_cast<std::uint16_t>(kCapacity - size_); }
  bool empty() const { return size_ == 0; }

  // false when full (callers check free_slots() for a whole report first, so this never drops a note).
  bool push(const synth::Note& note, std::uint16_t seq, std::uint8_t index);
  const QueuedNote& top() const { return heap_[0]; }  // only when !empty()
  void pop();
  void clear() { size_ = 0; }

  // The schedule's order: start tick, then arrival.
  static bool before(const QueuedNote& a, const QueuedNote& b);

 private:
  QueuedNote heap_[kCapacity];
  std::uint16_t size_ = 0;
  std::uint32_t next_arrival_ = 0;
};

}  // namespace hmp::fw
