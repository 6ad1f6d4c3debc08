// Measured presets (`hmp envelope measure --out`, a [measured] table in the config): `--envelope measured`
// gives every note its program's; `auto` gives them to instruments Table 1 lacks and keeps Table 1's.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "host/common/error.hpp"
#include "host/config/config.hpp"
#include "host/haptics/haptic_track.hpp"
#include "host/midi/smf_reader.hpp"
#include "tests/support/midi_builder.hpp"

namespace {

using hmp::haptics::HapticOptions;

// Three tracks: a piano (program 0, not in Table 1), a flute (73, Table 1) and drums.
hmp::midi::Song song() {
  std::vector<midi_test::Events> tracks;
  for (auto [channel, program] : {std::pair{0, 0}, std::pair{1, 73}, std::pair{9, 0}}) {
    midi_test::Events e;
    e.program(0, channel, program).on(0, channel, 60).off(480, channel, 60).end();
    tracks.push_back(e);
  }
  return hmp::midi::read_smf(midi_test::smf(1, 480, tracks)).song;
}

HapticOptions with_measured_config() {
  const auto path = std::filesystem::temp_directory_path() / ("hmp-measured-" + std::to_string(::getpid()) + ".toml");
  std::ofstream(path) << "[presets.measured-000]\nattack_ms = 9\ndecay_ms = 500\nrelease_ms = 300\n"
                         "sustain_pct = 5\nfinal_pct = 1\n"
                         "[presets.measured-073]\nattack_ms = 200\ndecay_ms = 0\nrelease_ms = 190\n"
                         "sustain_pct = 84\nfinal_pct = 1\n"
                         "[measured]\n\"0\" = \"measured-000\"\n\"73\" = \"measured-073\"\n";
  HapticOptions o;
  hmp::haptics::apply_config(hmp::config::load(path.string()), o);
  std::filesystem::remove(path);
  return o;
}

std::string preset_of(const hmp::haptics::HapticTrack& t) { return t.slot_names.at(t.notes.at(0).note.preset); }

TEST(MeasuredEnvelope, MeasuredGivesEveryPitchedNoteItsProgramsPreset) {
  const auto s = song();
  HapticOptions o = with_measured_config();
  o.envelope = "measured";
  const auto piano = hmp::haptics::build_haptic_track(s, 0, o);
  EXPECT_EQ(preset_of(piano), "measured-000");
  ASSERT_EQ(piano.uploads.size(), 1u);
  EXPECT_FLOAT_EQ(piano.uploads[0].adsr.attack_ms, 9.0f);
  EXPECT_FLOAT_EQ(piano.uploads[0].adsr.sustain, 0.05f);
  EXPECT_EQ(preset_of(hmp::haptics::build_haptic_track(s, 1, o)), "measured-073");
  EXPECT_EQ(preset_of(hmp::haptics::build_haptic_track(s, 2, o)), "guitar") << "drums keep auto's";
}

TEST(MeasuredEnvelope, AutoUsesThemOnlyForInstrumentsTable1Lacks) {
  const auto s = song();
  const HapticOptions o = with_measured_config();
  EXPECT_EQ(preset_of(hmp::haptics::build_haptic_track(s, 0, o)), "measured-000");
  EXPECT_EQ(preset_of(hmp::haptics::build_haptic_track(s, 1, o)), "flute");
  HapticOptions plain;
  EXPECT_EQ(preset_of(hmp::haptics::build_haptic_track(s, 0, plain)), "harpsichord") << "design §6 without them";
  HapticOptions gm = with_measured_config();
  gm.gm_presets[0] = "organ";
  EXPECT_EQ(preset_of(hmp::haptics::build_haptic_track(s, 0, gm)), "organ") << "[gm] still wins";
}

TEST(MeasuredEnvelope, AProgramWithoutOneOrNoneConfiguredIsBadInput) {
  const auto s = song();
  HapticOptions none;
  none.envelope = "measured";
  EXPECT_THROW(hmp::haptics::validate(none), hmp::BadInput);
  HapticOptions partial = with_measured_config();
  partial.measured_presets.erase(73);
  partial.envelope = "measured";
  EXPECT_NO_THROW(hmp::haptics::build_haptic_track(s, 0, partial));
  EXPECT_THROW(hmp::haptics::build_haptic_track(s, 1, partial), hmp::BadInput);
  HapticOptions dangling = with_measured_config();
  dangling.measured_presets[5] = "nowhere";
  EXPECT_THROW(hmp::haptics::validate(dangling), hmp::BadInput);
}

}  // namespace
