#include "firmware/note_queue.hpp"

namespace hmp::fw {

bool NoteQueue::before(const QueuedNote& a, const QueuedNote& b) {
  if (a.note.start_tick != b.note.start_tick) return a.note.start_tick < b.note.start_tick;
  // Arrival numbers wrap after 2^32 notes; the queue never holds notes 2^31 arrivals apart.
  return static_cast<std::int32_t>(a.arrival - b.arrival) < 0;
}

bool NoteQueue::push(const synth::Note& note, std::uint16_t seq, std::uint8_t index) {
  if (size_ == kCapacity) return false;
  std::uint16_t i = size_++;
  const QueuedNote item{note, next_arrival_++, seq, index};
  // Sift up: move parents down until the new item's place is found.
  while (i > 0) {
    const auto parent = static_cast<std::uint16_t>((i - 1) / 2);
    if (!before(item, heap_[parent])) break;
    heap_[i] = heap_[parent];
    i = parent;
  }
  heap_[i] = item;
  return true;
}

void NoteQueue::pop() {
  if (size_ == 0) return;
  const QueuedNote last = heap_[--size_];
  std::uint16_t i = 0;
  // Sift down: move the smaller child up until the last item fits.
  for (;;) {
    const auto left = static_cast<std::uint16_t>(2 * i + 1);
    if (left >= size_) break;
    const auto right = static_cast<std::uint16_t>(left + 1);
    const std::uint16_t child = (right < size_ && before(heap_[right], heap_[left])) ? right : left;
    if (!before(heap_[child], last)) break;
    heap_[i] = heap_[child];
    i = child;
  }
  heap_[i] = last;
}

}  // namespace hmp::fw
