#pragma once
// General MIDI level 1 facts: the 128 program names and their 16 families, and the `auto` envelope
// preset of design §6 chosen from a note's program and channel.
#include <cstdint>

#include "shared/envelope/envelope.hpp"

namespace hmp::midi {

// GM1 sound set name of a program (0–127, as in the file; GM numbers them 1–128). Programs above 127
// (impossible in a MIDI data byte) give "".
const char* gm_program_name(std::uint8_t program);
// One of the 16 GM1 families ("Piano", "Chromatic Percussion", … "Sound Effects").
const char* gm_family_name(std::uint8_t program);
// What `hmp info` shows for a track's instrument: the program name, or "Percussion" on channel 10.
const char* gm_instrument_name(std::uint8_t program, std::uint8_t channel);

// design §6 `auto`: Piano/Chromatic → harpsichord; Organ → organ; Guitar → guitar; Bass → contrabass;
// Strings 40/41 violin, 42 cello, 43 contrabass, 44–47 guitar; Ensemble → violin; Brass → trumpet;
// Reed/Pipe → flute; Synth lead → organ; Synth pad → violin; anything else → square.
// Channel 10 (index 9, drums) → guitar, whatever the program.
envelope::Preset auto_preset(std::uint8_t program, std::uint8_t channel);
// Table 1's eight measured instruments as GM programs: each is the programs first…last (organ: the five
// organs 16–20; guitar: nylon and steel 24–25; the others one program), `typical` the one that stands for
// it (`hmp envelope measure` measures that one by default).
struct Table1Instrument {
  envelope::Preset preset;
  std::uint8_t first, last, typical;
};
inline constexpr Table1Instrument kTable1Instruments[] = {
    {envelope::Preset::organ, 16, 20, 19},      {envelope::Preset::flute, 73, 73, 73},
    {envelope::Preset::harpsichord, 6, 6, 6},   {envelope::Preset::guitar, 24, 25, 24},
    {envelope::Preset::trumpet, 56, 56, 56},    {envelope::Preset::violin, 40, 40, 40},
    {envelope::Preset::cello, 42, 42, 42},      {envelope::Preset::contrabass, 43, 43, 43},
};
// Whether `program` is one of them: `auto` keeps Table 1's envelope for these even when measured
// presets are configured.
bool table1_instrument(std::uint8_t program);
// design §6: drum notes (channel 10) are felt at a constant frequency rather than mapped from the key.
inline bool auto_constant_frequency(std::uint8_t channel) { return channel == 9; }

}  // namespace hmp::midi
