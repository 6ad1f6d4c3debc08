// GM1 names and families, and the `auto` envelope preset of design §6.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "host/midi/gm.hpp"

using hmp::envelope::Preset;
using namespace hmp::midi;

TEST(MidiGm, NamesAreDistinctAndSpotChecked) {
  std::set<std::string> names;
  for (int p = 0; p < 128; ++p) {
    const std::string n = gm_program_name(static_cast<std::uint8_t>(p));
    EXPECT_FALSE(n.empty()) << p;
    names.insert(n);
  }
  EXPECT_EQ(names.size(), 128u);
  // The demo song's line-up (tests/data/midi/README.md): Flute 73, Violin 40, Viola 41, Cello 42, Contrabass 43,
  // Harpsichord 6.
  EXPECT_STREQ(gm_program_name(73), "Flute");
  EXPECT_STREQ(gm_program_name(40), "Violin");
  EXPECT_STREQ(gm_program_name(41), "Viola");
  EXPECT_STREQ(gm_program_name(42), "Cello");
  EXPECT_STREQ(gm_program_name(43), "Contrabass");
  EXPECT_STREQ(gm_program_name(6), "Harpsichord");
  EXPECT_STREQ(gm_program_name(0), "Acoustic Grand Piano");
  EXPECT_STREQ(gm_program_name(56), "Trumpet");
  EXPECT_STREQ(gm_program_name(127), "Gunshot");
  EXPECT_STREQ(gm_program_name(200), "");
  EXPECT_STREQ(gm_instrument_name(0, 9), "Percussion");
  EXPECT_STREQ(gm_instrument_name(42, 3), "Cello");
}

TEST(MidiGm, FamiliesAreEightProgramsEach) {
  const char* expected[16] = {"Piano",         "Chromatic Percussion",
                              "Organ",         "Guitar",
                              "Bass",          "Strings",
                              "Ensemble",      "Brass",
                              "Reed",          "Pipe",
                              "Synth Lead",    "Synth Pad",
                              "Synth Effects", "Ethnic",
                              "Percussive",    "Sound Effects"};
  for (int p = 0; p < 128; ++p) EXPECT_STREQ(gm_family_name(static_cast<std::uint8_t>(p)), expected[p / 8]) << p;
}

TEST(MidiGm, AutoPresetFollowsSpecTable) {
  // design §6, written out program range by program range.
  auto expect_range = [](int lo, int hi, Preset want) {
    for (int p = lo; p <= hi; ++p) {
      EXPECT_EQ(auto_preset(static_cast<std::uint8_t>(p), 0), want) << "program " << p;
    }
  };
  expect_range(0, 15, Preset::harpsichord);  // Piano, Chromatic Percussion
  expect_range(16, 23, Preset::organ);
  expect_range(24, 31, Preset::guitar);
  expect_range(32, 39, Preset::contrabass);  // Bass
  expect_range(40, 41, Preset::violin);
  expect_range(42, 42, Preset::cello);
  expect_range(43, 43, Preset::contrabass);
  expect_range(44, 47, Preset::guitar);
  expect_range(48, 55, Preset::violin);   // Ensemble
  expect_range(56, 63, Preset::trumpet);  // Brass
  expect_range(64, 79, Preset::flute);    // Reed, Pipe
  expect_range(80, 87, Preset::organ);    // Synth Lead
  expect_range(88, 95, Preset::violin);   // Synth Pad
  expect_range(96, 127, Preset::square);  // everything else
}

TEST(MidiGm, DrumChannelIsGuitarAtConstantFrequency) {
  for (int p = 0; p < 128; ++p) EXPECT_EQ(auto_preset(static_cast<std::uint8_t>(p), 9), Preset::guitar);
  EXPECT_TRUE(auto_constant_frequency(9));
  EXPECT_FALSE(auto_constant_frequency(0));
  EXPECT_FALSE(auto_constant_frequency(10));
  EXPECT_EQ(auto_preset(73, 10), Preset::flute);  // channel 11 is not drums
}

// The `auto` table's rows (shared/envelope/gm_auto.hpp) carry GM1's own names: a whole family's name for a
// row of exactly that family, otherwise its programs' names in order.
TEST(MidiGm, AutoRowsCarryGmNames) {
  for (const hmp::envelope::GmAutoRow& row : hmp::envelope::kGmAutoRows) {
    const bool whole_family = row.first % 8 == 0 && row.last == row.first + 7;
    std::string want;
    if (whole_family) {
      want = gm_family_name(row.first);
    } else {
      for (int p = row.first; p <= row.last; ++p) {
        if (!want.empty()) want += ", ";
        want += gm_program_name(static_cast<std::uint8_t>(p));
      }
    }
    EXPECT_EQ(row.gm_name, want) << "programs " << int{row.first} << "–" << int{row.last};
  }
}

// A program is found by its GM number (1–128) or its name in any case; nothing else is one.
TEST(MidiGm, ProgramsAreFoundByNumberOrName) {
  EXPECT_EQ(find_gm_program("1"), 0);
  EXPECT_EQ(find_gm_program("128"), 127);
  EXPECT_EQ(find_gm_program("violin"), 40);
  EXPECT_EQ(find_gm_program("ACOUSTIC GRAND PIANO"), 0);
  for (int p = 0; p < 128; ++p) EXPECT_EQ(find_gm_program(gm_program_name(static_cast<std::uint8_t>(p))), p);
  for (const char* bad : {"0", "129", "-1", "", "viol", "40x", " violin"}) EXPECT_FALSE(find_gm_program(bad)) << bad;
}

// Every program has a range of at least an octave on the MIDI keys, and an instrument's range holds the
// notes that define it: the open strings (violin G3, viola C3, cello C2, contrabass E1 and bass E1, guitar
// E2 … E4), the flute's and the piano's lowest and highest notes, the B♭ trumpet's low E3 as heard.
TEST(MidiGm, KeyRangesHoldTheInstrumentsDefiningNotes) {
  for (int p = 0; p < 128; ++p) {
    const KeySpan r = gm_key_range(static_cast<std::uint8_t>(p));
    EXPECT_GE(r.low, 0) << p;
    EXPECT_LE(r.high, 127) << p;
    EXPECT_GE(r.high - r.low, 12) << gm_program_name(static_cast<std::uint8_t>(p));
  }
  const auto holds = [](const char* instrument, std::initializer_list<int> keys) {
    const KeySpan r = gm_key_range(*find_gm_program(instrument));
    for (const int k : keys) EXPECT_TRUE(k >= r.low && k <= r.high) << instrument << " key " << k;
  };
  holds("Violin", {55, 62, 69, 76});
  holds("Viola", {48, 55, 62, 69});
  holds("Cello", {36, 43, 50, 57});
  holds("Contrabass", {28, 33, 38, 43});
  holds("Electric Bass (finger)", {28, 33, 38, 43});
  holds("Acoustic Guitar (nylon)", {40, 45, 50, 55, 59, 64});
  holds("Flute", {60, 96});
  holds("Acoustic Grand Piano", {21, 108});
  holds("Trumpet", {52});
  EXPECT_EQ(gm_key_range(40).low, 55) << "nothing below the violin's G string";
  EXPECT_EQ(gm_key_range(43).low, 28) << "nothing below the contrabass's E string";
}
