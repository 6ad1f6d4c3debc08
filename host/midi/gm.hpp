#pragma once
// General MIDI level 1 facts: the 128 program names and their 16 families.
#include <cstdint>
#include <optional>
#include <string_view>

#include "shared/envelope/gm_auto.hpp"

namespace hmp::midi {

// GM1 sound set name of a program (0–127, as in the file; GM numbers them 1–128). Programs above 127
// (impossible in a MIDI data byte) give "".
const char* gm_program_name(std::uint8_t program);
// A program given by a user: its GM number 1–128, or its GM1 name in any case ("violin", "Acoustic Grand
// Piano"); the program 0–127, or nullopt.
std::optional<std::uint8_t> find_gm_program(std::string_view text);
// The keys an instrument of a GM program plays: its usual sounding range as orchestration references give
// it (violin G3–A7 = 55–105, cello C2–A5, flute C4–D7, …), per family with the instruments that differ
// from their family named; synthesizers (leads, pads, effects) a 61-key keyboard, C2–C7; the sound
// effects the piano's 88 keys. `hmp live` spreads its pitch mapping over it.
struct KeySpan {
  int low = 21, high = 108;
};
KeySpan gm_key_range(std::uint8_t program);

// One of the 16 GM1 families ("Piano", "Chromatic Percussion", … "Sound Effects").
const char* gm_family_name(std::uint8_t program);
// What `hmp info` shows for a track's instrument: the program name, or "Percussion" on channel 10.
const char* gm_instrument_name(std::uint8_t program, std::uint8_t channel);

// The `auto` envelope of a GM program and Table 1's instruments as GM programs live with the presets, in
// shared/envelope/gm_auto.hpp; these names keep them reachable from here for callers that spell them
// midi::auto_preset, midi::kTable1Instruments and midi::table1_instrument.
using envelope::auto_preset;
using envelope::kTable1Instruments;
using envelope::table1_instrument;
using envelope::Table1Instrument;
// design §6: drum notes (channel 10) are felt at a constant frequency rather than mapped from the key.
inline bool auto_constant_frequency(std::uint8_t channel) { return channel == 9; }

}  // namespace hmp::midi
