// Song helpers: `--track` lookup (design §3), per-track note lists, track statistics.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "host/common/error.hpp"
#include "host/midi/smf_reader.hpp"
#include "tests/support/midi_builder.hpp"

using namespace midi_test;
using namespace hmp::midi;

namespace {

Song demo() {
  Events conductor;
  conductor.name(0, "Flute concerto").end();  // a name that matches "flute" but has no notes
  Events flute;
  flute.name(0, "Solo").program(0, 0, 73).on(0, 0, 72).off(10, 0, 72).on(5, 0, 74).off(10, 0, 74).end();
  Events strings;
  strings.name(0, "Violino I").program(0, 1, 40).on(0, 1, 60).on(3, 1, 67).off(7, 1, 60).off(0, 1, 67).end();
  Events drums;
  drums.on(0, 9, 36).off(1, 9, 36).end();
  return read_smf(smf(1, 96, {conductor, flute, strings, drums})).song;
}

}  // namespace

TEST(MidiSong, FindTrackByIndexNameOrInstrument) {
  const Song s = demo();
  EXPECT_EQ(find_track(s, "2"), 2u);
  EXPECT_EQ(find_track(s, "0"), 0u);
  EXPECT_FALSE(find_track(s, "4").has_value());
  EXPECT_FALSE(find_track(s, "-1").has_value());
  EXPECT_EQ(find_track(s, "flute"), 1u);  // GM name of track 1 beats the note-less conductor's name
  EXPECT_EQ(find_track(s, "FLUTE"), 1u);
  EXPECT_EQ(find_track(s, "concerto"), 0u);  // only the conductor matches
  EXPECT_EQ(find_track(s, "violino"), 2u);   // track name
  EXPECT_EQ(find_track(s, "violin"), 2u);    // name and GM name
  EXPECT_EQ(find_track(s, "percussion"), 3u);
  EXPECT_FALSE(find_track(s, "tuba").has_value());
  EXPECT_FALSE(find_track(s, "").has_value());
}

TEST(MidiSong, TrackNotesAndStatistics) {
  const Song s = demo();
  const std::vector<Note> strings = s.track_notes(2);
  ASSERT_EQ(strings.size(), 2u);
  EXPECT_EQ(strings[0].key, 60);
  EXPECT_EQ(strings[1].key, 67);
  EXPECT_EQ(strings[0].end_tick, 10u);
  EXPECT_TRUE(s.track_notes(0).empty());
  EXPECT_TRUE(s.track_notes(99).empty());

  const Track& t = s.tracks[1];
  EXPECT_EQ(t.note_count, 2u);
  EXPECT_EQ(t.key_min(), 72);
  EXPECT_EQ(t.key_max(), 74);
  EXPECT_EQ(t.distinct_keys(), 2);
  EXPECT_EQ(t.program(), 73);
  EXPECT_EQ(t.channel(), 0);
  EXPECT_FALSE(t.is_drums());
  EXPECT_TRUE(s.tracks[3].is_drums());
  EXPECT_EQ(s.tracks[3].key_min(), 36);
  EXPECT_EQ(s.tracks[0].distinct_keys(), 0);
}

TEST(MidiSong, KeyRangeAtTheExtremes) {
  Events t;
  t.on(0, 0, 0).off(1, 0, 0).on(0, 0, 127).off(1, 0, 127).on(0, 0, 63).off(1, 0, 63).on(0, 0, 64).off(1, 0, 64).end();
  const Song s = read_smf(smf(1, 96, {t})).song;
  EXPECT_EQ(s.tracks[0].key_min(), 0);
  EXPECT_EQ(s.tracks[0].key_max(), 127);
  EXPECT_EQ(s.tracks[0].distinct_keys(), 4);
}

TEST(MidiSong, LoadSongReadsFilesAndNamesThePathOnFailure) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("hmp_midi_song_test_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::filesystem::path good = dir / "scale.mid";
  Events t;
  t.on(0, 0, 60).off(96, 0, 60).end();
  const Bytes bytes = smf(1, 96, {t});
  std::ofstream(good, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  EXPECT_EQ(load_song(good).song.notes.size(), 1u);

  auto message = [](const std::filesystem::path& p) -> std::string {
    try {
      load_song(p);
    } catch (const hmp::BadInput& e) {
      return e.what();
    }
    return "(no error)";
  };
  const std::string missing = message(dir / "missing.mid");
  EXPECT_NE(missing.find("missing.mid"), std::string::npos) << missing;
  const std::string directory = message(dir);
  EXPECT_EQ(directory, dir.string() + ": is a directory");
  std::filesystem::remove_all(dir);
}
