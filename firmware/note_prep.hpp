#pragma once
// Voices prepared ahead of their tick (docs/firmware.md, "Note starts"). Setting up a voice costs ~1,900
// Cortex-M4F instructions (the envelope's phase boundaries are placed in software double), far more than
// the 16-voice tick itself, so the tick does not do it when it can help it: it takes the notes due within
// the next few milliseconds out of the schedule and hands them to the core's background context
// (Core::poll, the board's main loop), which prepares their voices; on the note's tick the tick only
// copies the prepared voice in. A note whose voice is not ready on its tick (the background did not get
// to it, or the preset or settings changed meanwhile) is set up by the tick itself, as before: notes start
// on their tick either way.
//
// Lock-free between the two contexts, no allocation. The tick owns the slots, the pending order and the
// generations; requests go to the background through an SPSC ring (copied by value: the background never
// reads what the tick may rewrite); the background writes a slot's voice and then publishes the request's
// generation in the slot's `ready` word (release). The tick uses a voice only if `ready` equals the
// generation it gave the slot (acquire): a voice being written, or one prepared for a note the tick has
// since started itself or dropped, carries another generation and is ignored. The background handles
// requests in order and a slot is reused only after the tick let go of it, so once `ready` matches, no
// write to that voice is pending.
#include <atomic>
#include <cstdint>

#include "firmware/note_queue.hpp"
#include "firmware/spsc_queue.hpp"
#include "shared/envelope/envelope.hpp"
#include "shared/synth/voice.hpp"

namespace hmp::fw {

class NotePrep {
 public:
  // Pending notes (each with a voice slot): a 16-note chord can be prepared whole.
  static constexpr std::uint8_t kSlots = 16;

  // ---- tick context ----
  // Room for another request (a free slot, and room in the ring: requests the background has not taken
  // yet, dropped or not, still occupy it).
  bool can_request() const { return count_ < kSlots && requests_.has_room(); }
  // Takes a note out of the schedule: its voice is to be prepared with this preset and config (copied).
  // Only when can_request().
  void request(const QueuedNote& q, const envelope::Adsr& preset, const synth::SynthConfig& cfg);
  std::uint8_t pending() const { return count_; }
  // The earliest pending note by (start tick, arrival), or nullptr.
  const QueuedNote* front() const { return count_ != 0 ? &notes_[order_[head_]] : nullptr; }
  // front()'s prepared voice, or nullptr if it is not (yet, or any longer) valid.
  const synth::Voice* front_voice() const;
  void pop_front();
  // Forget every pending note (the schedule was flushed).
  void clear();
  // Keep the pending notes but disown their voices: they were prepared with a preset or config that has
  // changed. Those notes are set up by the tick when due.
  void invalidate();

  // ---- background context ----
  // Prepares the voice of the oldest request; false if there was none.
  bool prepare_one();

 private:
  struct Request {
    synth::Note note;
    envelope::Adsr preset;
    synth::SynthConfig cfg;
    std::uint32_t generation = 0;
    std::uint8_t slot = 0;
  };
  struct Slot {
    synth::Voice voice;                   // written by the background only
    std::atomic<std::uint32_t> ready{0};  // generation of the request the voice was prepared for
  };
  static_assert(kSlots <= 16, "free_ is a 16-bit mask");
  static_assert((kSlots & (kSlots - 1)) == 0, "order_ is a ring indexed modulo kSlots");
  static constexpr std::uint8_t kMask = kSlots - 1;

  std::uint8_t take_free_slot();

  // Shared with the background.
  SpscQueue<Request, kSlots> requests_;  // dropped requests wait here until the background skips them
  Slot slots_[kSlots];
  // Tick-owned.
  QueuedNote notes_[kSlots];
  std::uint32_t generation_[kSlots]{};  // the current request's generation per slot; 0 is never used
  std::uint8_t order_[kSlots]{};        // ring of the pending slots from head_, earliest note first
  std::uint8_t head_ = 0;
  std::uint8_t count_ = 0;
  std::uint16_t free_ = 0xFFFF;  // bit i: slot i is free
};

}  // namespace hmp::fw
