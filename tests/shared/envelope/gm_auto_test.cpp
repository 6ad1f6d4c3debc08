// The `auto` envelope of design §6 (shared/envelope/gm_auto.hpp) against a listing typed in here from
// docs/design.md: the preset of every GM program 0–127 and of the drum channel, and the envelope each of
// them stands for, from Table 1 as design §6 prints it, compared bit for bit with what the presets hold.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <string>

#include "shared/envelope/envelope.hpp"
#include "shared/envelope/gm_auto.hpp"
#include "design_presets.hpp"

namespace {

using hmp::envelope::Adsr;
using hmp::envelope::Preset;
using hmp::envelope::Shape;

// design §6, "`auto` chooses by General MIDI program", family by family (eight programs each).
// clang-format off
const char* const kAutoByProgram[128] = {
    // Piano → harpsichord
    "harpsichord", "harpsichord", "harpsichord", "harpsichord",
    "harpsichord", "harpsichord", "harpsichord", "harpsichord",
    // Chromatic Percussion → harpsichord
    "harpsichord", "harpsichord", "harpsichord", "harpsichord",
    "harpsichord", "harpsichord", "harpsichord", "harpsichord",
    // Organ → organ
    "organ", "organ", "organ", "organ", "organ", "organ", "organ", "organ",
    // Guitar → guitar
    "guitar", "guitar", "guitar", "guitar", "guitar", "guitar", "guitar", "guitar",
    // Bass → contrabass
    "contrabass", "contrabass", "contrabass", "contrabass", "contrabass", "contrabass", "contrabass", "contrabass",
    // Strings: 40/41 → violin, 42 → cello, 43 → contrabass, 44–47 → guitar
    "violin", "violin", "cello", "contrabass", "guitar", "guitar", "guitar", "guitar",
    // Ensemble → violin
    "violin", "violin", "violin", "violin", "violin", "violin", "violin", "violin",
    // Brass → trumpet
    "trumpet", "trumpet", "trumpet", "trumpet", "trumpet", "trumpet", "trumpet", "trumpet",
    // Reed → flute
    "flute", "flute", "flute", "flute", "flute", "flute", "flute", "flute",
    // Pipe → flute
    "flute", "flute", "flute", "flute", "flute", "flute", "flute", "flute",
    // Synth Lead → organ
    "organ", "organ", "organ", "organ", "organ", "organ", "organ", "organ",
    // Synth Pad → violin
    "violin", "violin", "violin", "violin", "violin", "violin", "violin", "violin",
    // Synth Effects, Ethnic, Percussive, Sound Effects: anything else → square
    "square", "square", "square", "square", "square", "square", "square", "square",
    "square", "square", "square", "square", "square", "square", "square", "square",
    "square", "square", "square", "square", "square", "square", "square", "square",
    "square", "square", "square", "square", "square", "square", "square", "square",
};
// clang-format on

using Table1Row = hmp::test::DesignPreset;
constexpr const auto& kTable1 = hmp::test::kDesignPresets;

const Table1Row& table1_row(const std::string& name) {
  for (const Table1Row& row : kTable1) {
    if (name == row.name) return row;
  }
  ADD_FAILURE() << "no Table 1 row for " << name;
  return kTable1[0];
}

std::uint32_t bits(float v) { return std::bit_cast<std::uint32_t>(v); }

// The preset `got` is the envelope `want` names, field for field and bit for bit.
void expect_envelope(Preset got, const char* want, const std::string& where) {
  EXPECT_STREQ(hmp::envelope::name(got), want) << where;
  const Table1Row& row = table1_row(want);
  const Adsr& a = hmp::envelope::builtin(got);
  EXPECT_EQ(a.shape, Shape::adsr) << where;
  EXPECT_EQ(bits(a.attack_ms), bits(static_cast<float>(row.a_ms))) << where;
  EXPECT_EQ(bits(a.decay_ms), bits(static_cast<float>(row.dc_ms))) << where;
  EXPECT_EQ(bits(a.release_ms), bits(static_cast<float>(row.r_ms))) << where;
  EXPECT_EQ(bits(a.sustain), bits(static_cast<float>(row.s_pct / 100))) << where;
  EXPECT_EQ(bits(a.final_ratio), bits(static_cast<float>(row.r_pct / 100))) << where;
}

TEST(GmAuto, EveryProgramOnEveryMelodicChannel) {
  for (int channel = 0; channel < 16; ++channel) {
    if (channel == 9) continue;
    for (int program = 0; program < 128; ++program) {
      const Preset got =
          hmp::envelope::auto_preset(static_cast<std::uint8_t>(program), static_cast<std::uint8_t>(channel));
      expect_envelope(got, kAutoByProgram[program],
                      "program " + std::to_string(program) + " channel " + std::to_string(channel));
    }
  }
}

TEST(GmAuto, DrumChannelIsGuitarWhateverTheProgram) {
  for (int program = 0; program < 256; ++program) {
    const Preset got = hmp::envelope::auto_preset(static_cast<std::uint8_t>(program), 9);
    expect_envelope(got, "guitar", "drums, program " + std::to_string(program));
  }
}

TEST(GmAuto, ProgramsBeyondMidiAreSquare) {
  for (int program = 128; program < 256; ++program) {
    expect_envelope(hmp::envelope::auto_preset(static_cast<std::uint8_t>(program), 0), "square",
                    "program " + std::to_string(program));
  }
}

TEST(GmAuto, RowsNameTheirPresetsAndRoundTrip) {
  for (const hmp::envelope::GmAutoRow& row : hmp::envelope::kGmAutoRows) {
    const char* name = hmp::envelope::name(row.preset);
    Preset found{};
    ASSERT_TRUE(hmp::envelope::find_builtin(name, found)) << row.gm_name;
    EXPECT_EQ(found, row.preset) << row.gm_name;
    EXPECT_STREQ(hmp::envelope::name(found), name) << row.gm_name;
    EXPECT_GT(std::strlen(row.gm_name), 0u);
  }
}

// design §6: Table 1's eight are programs 6, 16–20, 24–25, 40, 42, 43, 56, 73.
TEST(GmAuto, Table1InstrumentsAreTheDocumentedPrograms) {
  for (int program = 0; program < 256; ++program) {
    const bool want = program == 6 || (program >= 16 && program <= 20) || program == 24 || program == 25 ||
                      program == 40 || program == 42 || program == 43 || program == 56 || program == 73;
    EXPECT_EQ(hmp::envelope::table1_instrument(static_cast<std::uint8_t>(program)), want) << program;
  }
  // Each instrument's typical program is one of its own, and `auto` gives all of them its preset.
  for (const hmp::envelope::Table1Instrument& i : hmp::envelope::kTable1Instruments) {
    EXPECT_GE(i.typical, i.first);
    EXPECT_LE(i.typical, i.last);
    for (int p = i.first; p <= i.last; ++p) {
      EXPECT_EQ(hmp::envelope::auto_preset(static_cast<std::uint8_t>(p), 0), i.preset) << p;
    }
  }
}

}  // namespace
