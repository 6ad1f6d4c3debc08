#pragma once
// The `auto` envelope of design §6: the built-in preset a note gets from its General MIDI program and
// channel, and Table 1's eight measured instruments as GM programs. Header-only and constexpr: the host
// chooses envelopes with it (host/haptics, host/cli), the firmware never does, so nothing of it is
// compiled into the firmware.
#include <cstdint>

#include "shared/envelope/envelope.hpp"

namespace hmp::envelope {

// One row of the `auto` table: the GM programs first … last (0–127, as in the file; GM numbers them
// 1–128), named as GM1 names them — the family's name when the row is a whole family of eight, else the
// names of its programs — and the preset they get.
struct GmAutoRow {
  const char* gm_name;
  std::uint8_t first, last;
  Preset preset;
};

// design §6, in program order; the rows cover 0–127 without gaps or overlaps (checked below).
inline constexpr GmAutoRow kGmAutoRows[] = {
    {"Piano", 0, 7, Preset::harpsichord},
    {"Chromatic Percussion", 8, 15, Preset::harpsichord},
    {"Organ", 16, 23, Preset::organ},
    {"Guitar", 24, 31, Preset::guitar},
    {"Bass", 32, 39, Preset::contrabass},
    {"Violin, Viola", 40, 41, Preset::violin},  // the Strings family, split by instrument
    {"Cello", 42, 42, Preset::cello},
    {"Contrabass", 43, 43, Preset::contrabass},
    {"Tremolo Strings, Pizzicato Strings, Orchestral Harp, Timpani", 44, 47, Preset::guitar},
    {"Ensemble", 48, 55, Preset::violin},
    {"Brass", 56, 63, Preset::trumpet},
    {"Reed", 64, 71, Preset::flute},
    {"Pipe", 72, 79, Preset::flute},
    {"Synth Lead", 80, 87, Preset::organ},
    {"Synth Pad", 88, 95, Preset::violin},
    {"Synth Effects", 96, 103, Preset::square},
    {"Ethnic", 104, 111, Preset::square},
    {"Percussive", 112, 119, Preset::square},
    {"Sound Effects", 120, 127, Preset::square},
};

// Channel 10 (index 9) is GM's percussion channel: its notes get one preset whatever the program.
inline constexpr std::uint8_t kGmDrumChannel = 9;
inline constexpr Preset kGmDrumPreset = Preset::guitar;
// A program outside 0–127 (impossible in a MIDI data byte).
inline constexpr Preset kGmOtherPreset = Preset::square;

namespace detail {
// auto_preset() finds a program's row by a scan that stops at the first row reaching it: that is right
// only if the rows run 0 … 127 in order, each starting where the previous one ended, and name presets.
constexpr bool gm_auto_rows_tile_programs() {
  unsigned next = 0;
  for (const GmAutoRow& row : kGmAutoRows) {
    if (row.first != next || row.last < row.first) return false;
    if (static_cast<std::uint8_t>(row.preset) >= kBuiltinCount) return false;
    next = row.last + 1u;
  }
  return next == 128;
}
}  // namespace detail
static_assert(detail::gm_auto_rows_tile_programs(), "kGmAutoRows must cover GM programs 0-127 in order");

// The `auto` preset of a note of `program` on `channel` (0-based).
constexpr Preset auto_preset(std::uint8_t program, std::uint8_t channel) {
  if (channel == kGmDrumChannel) return kGmDrumPreset;
  for (const GmAutoRow& row : kGmAutoRows) {
    if (program <= row.last) return row.preset;
  }
  return kGmOtherPreset;
}

// Table 1's eight measured instruments as GM programs: each is the programs first…last (organ: the five
// organs 16–20; guitar: nylon and steel 24–25; the others one program), `typical` the one that stands for
// it (`hmp envelope measure` measures that one by default).
struct Table1Instrument {
  Preset preset;
  std::uint8_t first, last, typical;
};
inline constexpr Table1Instrument kTable1Instruments[] = {
    {Preset::organ, 16, 20, 19},  {Preset::flute, 73, 73, 73},      {Preset::harpsichord, 6, 6, 6},
    {Preset::guitar, 24, 25, 24}, {Preset::trumpet, 56, 56, 56},    {Preset::violin, 40, 40, 40},
    {Preset::cello, 42, 42, 42},  {Preset::contrabass, 43, 43, 43},
};
// Whether `program` is one of them: `auto` keeps Table 1's envelope for these even when measured
// presets are configured.
constexpr bool table1_instrument(std::uint8_t program) {
  for (const Table1Instrument& i : kTable1Instruments) {
    if (program >= i.first && program <= i.last) return true;
  }
  return false;
}

}  // namespace hmp::envelope
