#include "firmware/note_prep.hpp"

namespace hmp::fw {

std::uint8_t NotePrep::take_free_slot() {
  std::uint8_t slot = 0;
  while (!(free_ & (1u << slot))) ++slot;  // can_request() guarantees a free one
  free_ = static_cast<std::uint16_t>(free_ & ~(1u << slot));
  return slot;
}

void NotePrep::request(const QueuedNote& q, const envelope::Adsr& preset, const synth::SynthConfig& cfg) {
  const std::uint8_t slot = take_free_slot();
  std::uint32_t& generation = generation_[slot];
  generation = generation + 1 != 0 ? generation + 1 : 1;
  notes_[slot] = q;
  // Into the pending order: usually last (notes leave the schedule in order), but a note that arrived
  // later for an earlier tick goes before the ones it precedes.
  std::uint8_t at = count_++;
  while (at > 0 && NoteQueue::before(q, notes_[order_[(head_ + at - 1) & kMask]])) {
    order_[(head_ + at) & kMask] = order_[(head_ + at - 1) & kMask];
    --at;
  }
  order_[(head_ + at) & kMask] = slot;

  Request* r = requests_.prepare();  // room: can_request()
  r->note = q.note;
  r->preset = preset;
  r->cfg = cfg;
  r->generation = generation;
  r->slot = slot;
  requests_.commit();
}

const synth::Voice* NotePrep::front_voice() const {
  if (count_ == 0) return nullptr;
  const std::uint8_t slot = order_[head_];
  return slots_[slot].ready.load(std::memory_order_acquire) == generation_[slot] ? &slots_[slot].voice : nullptr;
}

void NotePrep::pop_front() {
  if (count_ == 0) return;
  free_ = static_cast<std::uint16_t>(free_ | (1u << order_[head_]));
  head_ = static_cast<std::uint8_t>((head_ + 1) & kMask);
  --count_;
}

void NotePrep::clear() {
  invalidate();  // voices still being prepared for these notes must not match a later request
  count_ = 0;
  free_ = 0xFFFF;
}

void NotePrep::invalidate() {
  for (std::uint8_t i = 0; i < count_; ++i) {
    std::uint32_t& generation = generation_[order_[(head_ + i) & kMask]];
    generation = generation + 1 != 0 ? generation + 1 : 1;
  }
}

bool NotePrep::prepare_one() {
  const Request* r = requests_.front();
  if (r == nullptr) return false;
  Slot& s = slots_[r->slot];
  s.voice.prepare(r->note, r->preset, r->cfg);
  s.ready.store(r->generation, std::memory_order_release);
  requests_.pop();
  return true;
}

}  // namespace hmp::fw
