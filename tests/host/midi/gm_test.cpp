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
