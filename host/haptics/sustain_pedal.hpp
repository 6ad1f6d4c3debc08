#pragma once
// `--pedal` (design §17): a haptic note released while its channel's sustain pedal is down
// goes on until the pedal lifts, as the piano's string does. It ends earlier where the same key starts
// again on that channel (the key is struck anew), and at the song's end if the pedal never lifts.
// The pedal is down while CC64 ≥ 64; CC121 (reset all controllers) lifts it.
#include <cstdint>
#include <vector>

#include "host/midi/song.hpp"

namespace hmp::haptics {

// The end tick of each of `notes` (in order) with the pedal: its own end where the pedal is up then.
std::vector<std::uint64_t> pedal_end_ticks(const midi::Song& song, const std::vector<midi::Note>& notes);

}  // namespace hmp::haptics
