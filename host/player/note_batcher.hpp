#pragma once
// Notes in device ticks → note reports (docs/protocol.md, Note encoding): a Notes batch holds up to 5
// notes of one track whose starts lie within 255 ticks of the batch's base tick (the first note's),
// each at most kMaxCompactDuration ticks long; a longer note travels alone in a LongNote.
#include <cstddef>
#include <cstdint>
#include <span>

#include "shared/protocol/protocol.hpp"
#include "shared/synth/voice.hpp"

namespace hmp::player {

// One note ready for the device: note.start_tick is the device tick it starts on.
using DeviceNote = synth::Note;

// Fills `out` (seq 0: the sender numbers it) with the first report for `notes` (sorted by start tick,
// not empty) and returns how many of them it carries (≥ 1). A LongNote when the first note is too long
// for a compact note; otherwise a Notes batch that stops before a note of another track, a too-long
// note, or one starting more than 255 ticks after the first.
std::size_t make_report(std::span<const DeviceNote> notes, protocol::Message& out);

}  // namespace hmp::player
