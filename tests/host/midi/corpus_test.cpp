// Every MIDI file of the development corpus (tests/data/midi, design §4) has a pinned outcome here: its note
// count, logical track count and duration, or the exact start of its error message, and the warning it
// must produce (or none). A file added to or removed from the corpus without a pin fails the test.
//
// Where the pins come from:
// - jazz-soft/midi: each file's own text events say what a player must do ("You must hear a C-Major
//   scale", "must play sequentially", "after 5 seconds", …); the comment beside each pin quotes the point.
//   Files with illegal F1–FE bytes are errors by design §4 (their text: "Most players consider it invalid"),
//   and the illegal byte comes before the first note, so nothing is left to play.
// - music21 and classical: note counts and times were checked against an independent reading with
//   python3-mido 1.2.10 (first-in-first-out pairing, global tempo map: every note's ticks equal and its
//   times within 1 µs; durations equal to mido's MidiFile.length), and the track line-up against
//   tests/data/midi/README.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>

#include "host/common/error.hpp"
#include "host/midi/gm.hpp"
#include "host/midi/smf_reader.hpp"

namespace fs = std::filesystem;
using hmp::envelope::Preset;
using namespace hmp::midi;

namespace {

const fs::path kCorpus = fs::path(HMP_TEST_DATA_DIR) / "midi";

struct Pin {
  int notes = 0;
  int tracks = 0;
  double duration_s = 0;
  const char* warning = nullptr;  // a warning containing this must appear; nullptr: no warning at all
  const char* error = nullptr;    // read fails with a message starting with this
  bool c_major = false;           // the notes are the C-major scale C5…C6 (keys 60 … 72) in order
};

Pin ok(int notes, int tracks, double duration_s, const char* warning = nullptr) {
  return Pin{notes, tracks, duration_s, warning, nullptr, false};
}
Pin scale(int tracks, double duration_s, const char* warning = nullptr) {
  return Pin{8, tracks, duration_s, warning, nullptr, true};
}
Pin fails(const char* error) { return Pin{0, 0, 0, nullptr, error, false}; }

const std::map<std::string, Pin>& pins() {
  static const std::map<std::string, Pin> table = {
      // ---- jazz-soft/midi (96 ticks per quarter, no tempo event: 120 bpm, a quarter is 0.5 s) ----
      // "This file has two tracks instead of one": both scales are read, one logical track per channel.
      {"jazz-soft/midi/test-2-tracks-type-0.mid", ok(16, 2, 4.5, "format 0 file with more than one track chunk")},
      {"jazz-soft/midi/test-2-tracks-type-1.mid", ok(16, 2, 4.5)},        // "must play simultaneously"
      {"jazz-soft/midi/test-2-tracks-type-2.mid", ok(16, 2, 9.0)},        // "must play sequentially": twice as long
      {"jazz-soft/midi/test-all-gm-percussion.mid", ok(183, 1, 137.25)},  // keys 27–87, three strokes each
      {"jazz-soft/midi/test-all-gm-sounds.mid", ok(512, 1, 352.0)},       // 128 programs × 4 notes
      {"jazz-soft/midi/test-all-gm2-sounds.mid", ok(1060, 1, 728.75)},
      {"jazz-soft/midi/test-all-gs-sounds.mid", ok(5044, 1, 3467.75)},
      {"jazz-soft/midi/test-all-microsoft-gs-wavetable-synth-sounds.mid", ok(904, 1, 621.5)},
      {"jazz-soft/midi/test-all-xg-sounds.mid", ok(4560, 1, 3135.0)},
      {"jazz-soft/midi/test-c-major-scale.mid", scale(1, 4.0)},  // "You must hear a C-Major scale."
      // "Percussion sound on Channel 1 … Melody sound on Channel 10": 4 notes on each channel.
      {"jazz-soft/midi/test-control-00-20-bank-select.mid", ok(8, 2, 5.5)},
      {"jazz-soft/midi/test-control-40-damper.mid", ok(8, 1, 8.0)},              // two sequences of four
      {"jazz-soft/midi/test-control-41-portamento.mid", ok(8, 1, 7.0)},          // two sequences of four
      {"jazz-soft/midi/test-control-54-portamento-control.mid", ok(1, 1, 3.0)},  // one gliding note
      // Mode messages only ("Sending the … message"): no note.
      {"jazz-soft/midi/test-control-7c-omni-mode-off.mid", ok(0, 1, 0.5)},
      {"jazz-soft/midi/test-control-7d-omni-mode-on.mid", ok(0, 1, 0.5)},
      {"jazz-soft/midi/test-control-7e-mono-mode-on.mid", ok(0, 1, 0.5)},
      {"jazz-soft/midi/test-control-7f-poly-mode-on.mid", ok(0, 1, 0.5)},
      // "an extra byte in the end. Most players have no problem with that."
      {"jazz-soft/midi/test-corrupt-file-extra-byte.mid", scale(1, 4.0, "1 trailing bytes ignored")},
      // "missing the last byte": the End-of-Track's length byte; the scale is complete before it.
      {"jazz-soft/midi/test-corrupt-file-missing-byte.mid",
       scale(1, 4.0, "track 0 at byte 0x108: event cut off by the end of the file")},
      {"jazz-soft/midi/test-empty-file.mid", fails("empty file (0 bytes)")},
      {"jazz-soft/midi/test-empty.mid", ok(0, 1, 0.0)},  // one track holding only End-of-Track
      // "you must hear a dog": a 3-note doggy phrase.
      {"jazz-soft/midi/test-gm2-doggy-78-00-38-4c.mid", ok(3, 1, 1.5)},
      {"jazz-soft/midi/test-gm2-doggy-79-01-7b.mid", ok(3, 1, 1.5)},
      {"jazz-soft/midi/test-gs-doggy-01-00-7b.mid", ok(3, 1, 1.5)},
      // "illegal MIDI message(s) … Most players consider it invalid": error at the illegal byte.
      {"jazz-soft/midi/test-illegal-message-all.mid", fails("track 0 at byte 0xbb: illegal status byte 0xf1")},
      {"jazz-soft/midi/test-illegal-message-f1-xx.mid", fails("track 0 at byte 0xd8: illegal status byte 0xf1")},
      {"jazz-soft/midi/test-illegal-message-f2-xx-xx.mid", fails("track 0 at byte 0xdd: illegal status byte 0xf2")},
      {"jazz-soft/midi/test-illegal-message-f3-xx.mid", fails("track 0 at byte 0xd5: illegal status byte 0xf3")},
      {"jazz-soft/midi/test-illegal-message-f4.mid", fails("track 0 at byte 0xcd: illegal status byte 0xf4")},
      {"jazz-soft/midi/test-illegal-message-f5.mid", fails("track 0 at byte 0xcd: illegal status byte 0xf5")},
      {"jazz-soft/midi/test-illegal-message-f6.mid", fails("track 0 at byte 0xd0: illegal status byte 0xf6")},
      {"jazz-soft/midi/test-illegal-message-f8.mid", fails("track 0 at byte 0xd0: illegal status byte 0xf8")},
      {"jazz-soft/midi/test-illegal-message-f9.mid", fails("track 0 at byte 0xcd: illegal status byte 0xf9")},
      {"jazz-soft/midi/test-illegal-message-fa.mid", fails("track 0 at byte 0xc9: illegal status byte 0xfa")},
      {"jazz-soft/midi/test-illegal-message-fb.mid", fails("track 0 at byte 0xcc: illegal status byte 0xfb")},
      {"jazz-soft/midi/test-illegal-message-fc.mid", fails("track 0 at byte 0xc8: illegal status byte 0xfc")},
      {"jazz-soft/midi/test-illegal-message-fd.mid", fails("track 0 at byte 0xcd: illegal status byte 0xfd")},
      {"jazz-soft/midi/test-illegal-message-fe.mid", fails("track 0 at byte 0xd2: illegal status byte 0xfe")},
      // "Mary Was A Little Lame": lyrics track, melody track (29 notes, as mido reads them).
      {"jazz-soft/midi/test-karaoke-kar.mid", ok(29, 3, 10.600005)},
      // Chords of three notes on three channels, 8 chords.
      {"jazz-soft/midi/test-multichannel-chords-0.mid", ok(24, 3, 4.0)},  // format 0: split into 3 tracks
      {"jazz-soft/midi/test-multichannel-chords-1.mid", ok(24, 3, 4.0)},
      {"jazz-soft/midi/test-multichannel-chords-2.mid", ok(24, 2, 4.0)},  // 2 channels in one track
      {"jazz-soft/midi/test-multichannel-chords-3.mid", ok(24, 3, 4.0)},  // two tracks sharing a channel
      // "contains a non-MIDI track. Players should ignore it."
      {"jazz-soft/midi/test-non-midi-track.mid", scale(1, 4.0, "unknown chunk \"Junk\" (27 bytes) skipped")},
      {"jazz-soft/midi/test-not-a-midi-file.mid", fails("byte 0x0: not a MIDI file: no MThd header")},
      // "Playing C5 with different velocities": velocity 1, 16, 32, … 112, 127.
      {"jazz-soft/midi/test-note-on-velocity.mid", ok(9, 1, 4.5)},
      {"jazz-soft/midi/test-rpn-00-00-pitch-bend-range.mid", ok(5, 1, 29.5)},  // five bend ranges
      {"jazz-soft/midi/test-rpn-00-01-fine-tuning.mid", ok(25, 2, 12.5)},      // quarter-tone scale, 2 channels
      {"jazz-soft/midi/test-rpn-00-02-coarse-tuning.mid", ok(8, 1, 4.0)},      // scale by tuning one key
      {"jazz-soft/midi/test-rpn-00-05-modulation-depth-range.mid", ok(5, 1, 17.0)},
      // "Running status is interrupted by metaevent/SysEx in the middle of the scale" + "must hear a scale".
      {"jazz-soft/midi/test-running-status-metaevent.mid",
       scale(1, 4.0, "track 0 at byte 0xea: running status continues after a meta or sysex event")},
      {"jazz-soft/midi/test-running-status-sysex.mid",
       scale(1, 4.0, "track 0 at byte 0xe1: running status continues after a meta or sysex event")},
      // "should play nothing for 5 seconds" / "End-of-Track after 5 seconds".
      {"jazz-soft/midi/test-silence-all-notes-off.mid", ok(0, 1, 5.0)},
      {"jazz-soft/midi/test-silence-end-of-track.mid", ok(0, 1, 5.0)},
      {"jazz-soft/midi/test-silence-text-metaevent.mid", ok(0, 1, 5.0)},
      {"jazz-soft/midi/test-smpte-offset.mid", scale(1, 4.0)},  // "Most players will ignore it."
      // SysEx only: no note.
      {"jazz-soft/midi/test-sysex-7e-06-01-id-request.mid", ok(0, 1, 0.5)},
      {"jazz-soft/midi/test-sysex-7e-09-01-gm1-enable.mid", ok(0, 1, 0.5)},
      {"jazz-soft/midi/test-sysex-7e-09-02-gm-disable.mid", ok(0, 1, 0.5)},
      {"jazz-soft/midi/test-sysex-7e-09-03-gm2-enable.mid", ok(0, 1, 0.5)},
      {"jazz-soft/midi/test-sysex-7f-04-03-master-fine-tuning.mid", ok(5, 1, 2.5)},  // "quarter-tone sequence"
      // "must hear a C-Major scale" made by master tuning: key 60 on 8 channels (format 0 → 8 tracks).
      {"jazz-soft/midi/test-sysex-7f-04-04-master-coarse-tuning.mid", ok(8, 8, 4.0)},
      {"jazz-soft/midi/test-sysex-7x-08-0x-scale-tuning.mid", ok(65, 1, 34.5)},
      // Drum part on channel 0 and piano on channel 9: 4 notes each.
      {"jazz-soft/midi/test-sysex-gs-40-1x-15-drum-part-change.mid", ok(8, 2, 6.0)},
      {"jazz-soft/midi/test-sysex-gs-40-1x-4x-scale-tuning.mid", ok(3, 1, 1.5)},  // +63, −64, +63 cents
      // A raw SysEx dump, not an SMF.
      {"jazz-soft/midi/test-syx-7e-06-01-id-request.syx", fails("byte 0x0: not a MIDI file: no MThd header")},
      // "You must hear C5 and then the track ends after one half note": 0.5 s + 1.0 s.
      {"jazz-soft/midi/test-track-length.mid", ok(1, 1, 1.5)},
      // "2/3/4-byte VLQ delta times. Technically, it's a valid MIDI file." + scale.
      {"jazz-soft/midi/test-vlq-2-byte.mid", scale(1, 4.0)},
      {"jazz-soft/midi/test-vlq-3-byte.mid", scale(1, 4.0)},
      {"jazz-soft/midi/test-vlq-4-byte.mid", scale(1, 4.0)},
      {"jazz-soft/midi/test-xg-doggy-40-00-30.mid", ok(3, 1, 1.5)},
      {"jazz-soft/midi/test-xg-doggy-7e-00-00-54.mid", ok(3, 1, 1.5)},

      // ---- music21 ----
      {"music21/documentation/source/usersGuide/files/cs1-1pre.mid", ok(656, 17, 129.521122)},
      {"music21/music21/midi/testPrimitive/test01.mid", ok(18, 2, 3.96875)},
      {"music21/music21/midi/testPrimitive/test02.mid", ok(163, 5, 18.499963)},
      {"music21/music21/midi/testPrimitive/test03.mid", ok(1391, 4, 160.833483)},
      // 19 MTrk chunks although the header says 18 (the last three are empty).
      {"music21/music21/midi/testPrimitive/test04.mid",
       ok(6059, 19, 595.303331, "the header announces 18 tracks, the file has 19")},
      {"music21/music21/midi/testPrimitive/test05.mid", ok(13, 1, 7.242188)},
      {"music21/music21/midi/testPrimitive/test06.mid", ok(120, 1, 32.026042)},
      {"music21/music21/midi/testPrimitive/test07.mid", ok(318, 1, 58.850636)},
      {"music21/music21/midi/testPrimitive/test08.mid", ok(17, 1, 6.0)},
      {"music21/music21/midi/testPrimitive/test09.mid", ok(2875, 3, 135.624943)},
      {"music21/music21/midi/testPrimitive/test10.mid", ok(16, 1, 10.09848)},
      {"music21/music21/midi/testPrimitive/test11.mid", ok(48, 4, 10.590147)},
      {"music21/music21/midi/testPrimitive/test12.mid", ok(12, 5, 4.802344)},
      {"music21/music21/midi/testPrimitive/test13.mid", ok(8, 1, 6.002083)},
      {"music21/music21/midi/testPrimitive/test14.mid", ok(17, 2, 6.602344)},
      {"music21/music21/midi/testPrimitive/test15.mid", ok(5, 2, 0.499999)},
      {"music21/music21/midi/testPrimitive/test16.mid", ok(3, 1, 0.7375)},  // one zero-length note
      {"music21/music21/midi/testPrimitive/test17.mid", ok(53, 4, 6.000524)},
      {"music21/music21/midi/testPrimitive/test18.mid", ok(34, 2, 17.5)},
      {"music21/music21/midi/testPrimitive/test19.mid", ok(34, 2, 17.755208)},
      {"music21/music21/midi/testPrimitive/test20.mid", ok(34, 2, 17.5)},
      {"music21/music21/midi/testPrimitive/test21.mid", ok(34, 2, 17.755208)},
      {"music21/music21/omr/k525MIDIMvt1.mid", ok(6398, 6, 326.265473)},
      {"music21/music21/omr/k525short.mid", ok(211, 6, 16.365546)},

      // ---- classical (tests/data/midi/README.md) ----
      {"classical/bach-bwv1050-brandenburg5-mvt3-allegro.mid", ok(6006, 9, 310.0)},
      {"classical/bach-bwv1079-musical-offering-ricercar-a3.mid", ok(2316, 3, 370.0)},
  };
  return table;
}

bool is_midi_name(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".mid" || ext == ".midi" || ext == ".rmi" || ext == ".kar";
}

// jazz-soft/midi and classical: every file; music21 (a source tree with other files): MIDI files only.
std::set<std::string> corpus_files() {
  std::set<std::string> out;
  for (const char* folder : {"jazz-soft/midi", "classical", "music21"}) {
    const bool only_midi = std::string(folder) == "music21";
    for (const auto& e : fs::recursive_directory_iterator(kCorpus / folder)) {
      if (!e.is_regular_file()) continue;
      if (only_midi && !is_midi_name(e.path())) continue;
      out.insert(fs::relative(e.path(), kCorpus).generic_string());
    }
  }
  return out;
}

const Track& track_of(const Song& s, std::size_t i) { return s.tracks.at(i); }

}  // namespace

TEST(MidiCorpus, EveryFileIsPinnedAndEveryPinHasAFile) {
  const std::set<std::string> files = corpus_files();
  for (const auto& f : files) EXPECT_TRUE(pins().count(f) == 1) << "corpus file without a pin: " << f;
  for (const auto& [f, pin] : pins()) EXPECT_TRUE(files.count(f) == 1) << "pin without a corpus file: " << f;
  // Every folder is covered.
  for (const char* folder : {"jazz-soft/", "music21/", "classical/"}) {
    EXPECT_TRUE(std::any_of(files.begin(), files.end(), [&](const std::string& f) { return f.rfind(folder, 0) == 0; }))
        << folder;
  }
}

TEST(MidiCorpus, EveryFileHasItsPinnedOutcome) {
  for (const auto& [file, pin] : pins()) {
    SCOPED_TRACE(file);
    const fs::path path = kCorpus / file;
    if (!fs::exists(path)) continue;  // reported by the test above
    if (pin.error != nullptr) {
      try {
        load_song(path);
        ADD_FAILURE() << "expected an error starting with: " << pin.error;
      } catch (const hmp::BadInput& e) {
        // load_song names the file, then the reader's message (track and byte offset).
        EXPECT_EQ(std::string(e.what()).rfind(path.string() + ": " + pin.error, 0), 0u) << e.what();
      }
      continue;
    }
    ReadResult r;
    try {
      r = load_song(path);
    } catch (const hmp::BadInput& e) {
      ADD_FAILURE() << "unexpected error: " << e.what();
      continue;
    }
    const Song& s = r.song;
    EXPECT_EQ(s.notes.size(), static_cast<std::size_t>(pin.notes));
    EXPECT_EQ(s.tracks.size(), static_cast<std::size_t>(pin.tracks));
    EXPECT_NEAR(s.duration_s(), pin.duration_s, 2e-6);
    std::string warnings;
    for (const auto& w : r.warnings) warnings += w.message + "\n";
    if (pin.warning == nullptr) {
      EXPECT_TRUE(r.warnings.empty()) << warnings;
    } else {
      EXPECT_NE(warnings.find(pin.warning), std::string::npos) << warnings;
    }
    // Invariants of every song.
    std::uint32_t counted = 0;
    for (const Track& t : s.tracks) counted += t.note_count;
    EXPECT_EQ(counted, s.notes.size());
    for (const Note& n : s.notes) {
      EXPECT_LE(n.start_tick, n.end_tick);
      EXPECT_LE(s.end_us(n), s.duration_us);
      EXPECT_TRUE(s.tracks.at(n.track).has_channel(n.channel));
    }
    if (pin.c_major) {
      std::vector<Note> notes = s.notes;
      std::stable_sort(notes.begin(), notes.end(),
                       [](const Note& a, const Note& b) { return a.start_tick < b.start_tick; });
      const int want[8] = {60, 62, 64, 65, 67, 69, 71, 72};
      ASSERT_EQ(notes.size(), 8u);
      for (int i = 0; i < 8; ++i) {
        EXPECT_EQ(notes[static_cast<std::size_t>(i)].key, want[i]);
        const Note& n = notes[static_cast<std::size_t>(i)];
        EXPECT_NEAR(s.end_s(n) - s.start_s(n), 0.5, 1e-9);
      }
    }
  }
}

TEST(MidiCorpus, BrandenburgLineUpMatchesSources) {
  const Song s = load_song(kCorpus / "classical/bach-bwv1050-brandenburg5-mvt3-allegro.mid").song;
  EXPECT_EQ(s.format, 1);
  EXPECT_EQ(s.division.ticks_per_quarter, 384);
  ASSERT_EQ(s.tracks.size(), 9u);
  EXPECT_EQ(track_of(s, 0).note_count, 0u);  // conductor
  struct Want {
    int program;
    const char* gm;
    Preset preset;
  };
  const Want want[8] = {{73, "Flute", Preset::flute},
                        {40, "Violin", Preset::violin},
                        {40, "Violin", Preset::violin},
                        {41, "Viola", Preset::violin},
                        {42, "Cello", Preset::cello},
                        {43, "Contrabass", Preset::contrabass},
                        {6, "Harpsichord", Preset::harpsichord},
                        {6, "Harpsichord", Preset::harpsichord}};
  for (std::size_t i = 1; i < 9; ++i) {
    const Track& t = track_of(s, i);
    SCOPED_TRACE(i);
    EXPECT_GT(t.note_count, 0u);
    EXPECT_EQ(t.program(), want[i - 1].program);
    EXPECT_EQ(t.programs.size(), 1u);
    EXPECT_STREQ(gm_instrument_name(t.program(), t.channel()), want[i - 1].gm);
    EXPECT_EQ(auto_preset(t.program(), t.channel()), want[i - 1].preset);
  }
  EXPECT_EQ(track_of(s, 1).name, "flute");
}

TEST(MidiCorpus, RicercarHasNoProgramChange) {
  const Song s = load_song(kCorpus / "classical/bach-bwv1079-musical-offering-ricercar-a3.mid").song;
  for (const Note& n : s.notes) EXPECT_EQ(n.program, 0);
}

TEST(MidiCorpus, Format2PatternsPlayOneAfterAnother) {
  const Song s = load_song(kCorpus / "jazz-soft/midi/test-2-tracks-type-2.mid").song;
  ASSERT_EQ(s.tracks.size(), 2u);
  std::int64_t first_end = 0, second_start = INT64_MAX;
  for (const Note& n : s.notes) {
    if (n.track == 0) first_end = std::max(first_end, s.end_us(n));
    if (n.track == 1) second_start = std::min(second_start, s.start_us(n));
  }
  EXPECT_GE(second_start, first_end);
  EXPECT_EQ(s.tracks[0].end_us, 4500000);
}

TEST(MidiCorpus, NoteOnVelocityFileHasItsVelocities) {
  const Song s = load_song(kCorpus / "jazz-soft/midi/test-note-on-velocity.mid").song;
  const int want[9] = {1, 16, 32, 48, 64, 80, 96, 112, 127};  // its text events "Velocity = …"
  ASSERT_EQ(s.notes.size(), 9u);
  for (int i = 0; i < 9; ++i) {
    EXPECT_EQ(s.notes[static_cast<std::size_t>(i)].velocity, want[i]);
    EXPECT_EQ(s.notes[static_cast<std::size_t>(i)].key, 60);  // "Playing C5"
  }
}

TEST(MidiCorpus, AllGmSoundsPlaysEveryProgramInOrder) {
  // "Playing all General MIDI 1 sounds": programs 0 … 127 one after another, 4 notes each.
  const Song s = load_song(kCorpus / "jazz-soft/midi/test-all-gm-sounds.mid").song;
  std::vector<Note> notes = s.notes;
  std::stable_sort(notes.begin(), notes.end(),
                   [](const Note& a, const Note& b) { return a.start_tick < b.start_tick; });
  ASSERT_EQ(notes.size(), 512u);
  for (std::size_t i = 0; i < notes.size(); ++i) EXPECT_EQ(notes[i].program, i / 4) << i;
  EXPECT_EQ(s.tracks[0].programs.size(), 128u);
}

TEST(MidiCorpus, GmNamesAgreeWithTheAllGmSoundsTextEvents) {
  // The file's text events read "NNN Family: Name". Compare family exactly and the name ignoring case,
  // spaces and hyphens; GM1 calls program 54 "Synth Voice" where the file says "Synth Choir".
  std::ifstream in(kCorpus / "jazz-soft/midi/test-all-gm-sounds.mid", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto norm = [](std::string v) {
    std::string o;
    for (const char c : v) {
      if (c != ' ' && c != '-') o += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    return o;
  };
  const std::regex line(R"((\d{3}) ([A-Za-z ]+): (.+))");
  std::set<int> seen;
  for (std::size_t i = 0; (i = bytes.find("\xFF\x01", i)) != std::string::npos; i += 2) {
    if (i + 3 > bytes.size()) break;
    const auto len = static_cast<unsigned char>(bytes[i + 2]);
    if (len >= 0x80 || i + 3 + len > bytes.size()) continue;
    std::smatch m;
    const std::string text = bytes.substr(i + 3, len);
    if (!std::regex_match(text, m, line)) continue;
    const int program = std::stoi(m[1]);
    ASSERT_LT(program, 128);
    seen.insert(program);
    const auto p = static_cast<std::uint8_t>(program);
    EXPECT_EQ(m[2].str(), gm_family_name(p)) << program;
    if (program != 54) {
      EXPECT_EQ(norm(m[3]), norm(gm_program_name(p))) << program << " " << m[3];
    }
  }
  EXPECT_EQ(seen.size(), 128u);
}

TEST(MidiCorpus, PercussionFileIsAllDrums) {
  const Song s = load_song(kCorpus / "jazz-soft/midi/test-all-gm-percussion.mid").song;
  ASSERT_EQ(s.tracks.size(), 1u);
  EXPECT_TRUE(s.tracks[0].is_drums());
  EXPECT_EQ(s.tracks[0].key_min(), 27);  // "27 High-Q (GM2)"
  EXPECT_EQ(s.tracks[0].key_max(), 87);  // "87 Open Surdo (GM2)"
  EXPECT_EQ(s.tracks[0].distinct_keys(), 61);
  EXPECT_EQ(auto_preset(s.tracks[0].program(), s.tracks[0].channel()), Preset::guitar);
}

TEST(MidiCorpus, ZeroLengthNoteOfMusic21Test16IsKept) {
  const Song s = load_song(kCorpus / "music21/music21/midi/testPrimitive/test16.mid").song;
  const auto zero =
      std::count_if(s.notes.begin(), s.notes.end(), [](const Note& n) { return n.start_tick == n.end_tick; });
  EXPECT_EQ(zero, 1);
}
