#include "host/player/note_batcher.hpp"

namespace hmp::player {

namespace {
constexpr std::uint64_t kMaxOffset = 255;  // u8 offset from the batch's base tick
}

std::size_t make_report(std::span<const DeviceNote> notes, protocol::Message& out) {
  const DeviceNote& first = notes.front();
  if (first.duration_ticks > protocol::kMaxCompactDuration) {
    out = protocol::make(protocol::Type::long_note, 0);
    protocol::LongNote& l = out.long_note;
    l.track = first.track;
    l.preset = first.preset;
    l.start_tick = first.start_tick;
    l.duration_ticks = first.duration_ticks;
    l.freq_q20 = first.freq_q20;
    l.amp_q16 = first.amp_q16;
    return 1;
  }
  out = protocol::make(protocol::Type::notes, 0);
  protocol::Notes& batch = out.notes;
  batch.track = first.track;
  batch.base_tick = static_cast<std::uint32_t>(first.start_tick);  // the device extends the low 32 bits
  std::size_t n = 0;
  for (const DeviceNote& note : notes) {
    if (n == protocol::kNotesPerBatch || note.track != first.track || note.start_tick < first.start_tick ||
        note.start_tick - first.start_tick > kMaxOffset || note.duration_ticks > protocol::kMaxCompactDuration) {
      break;
    }
    protocol::CompactNote& c = batch.notes[n++];
    c.offset = static_cast<std::uint8_t>(note.start_tick - first.start_tick);
    c.preset = note.preset;
    c.duration_ticks = note.duration_ticks;
    c.freq_q20 = note.freq_q20;
    c.amp_q16 = note.amp_q16;
  }
  batch.count = static_cast<std::uint8_t>(n);
  return n;
}

}  // namespace hmp::player
