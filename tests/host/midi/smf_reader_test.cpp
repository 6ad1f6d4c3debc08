// SMF reader, one test per rule of design §4, on hand-built byte strings (see midi_builder.hpp).
// Offsets: MThd is 14 bytes, so the first MTrk's data starts at byte 22 (0x16).
#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "host/common/error.hpp"
#include "host/midi/smf_detail.hpp"
#include "host/midi/smf_reader.hpp"
#include "tests/support/midi_builder.hpp"

using namespace midi_test;
using hmp::midi::Note;
using hmp::midi::read_smf;
using hmp::midi::ReadResult;

namespace {

ReadResult read(const Bytes& b) { return read_smf(b); }

std::string error_of(const Bytes& b) {
  try {
    read_smf(b);
  } catch (const hmp::BadInput& e) {
    return e.what();
  }
  return "(no error)";
}

bool has_warning(const ReadResult& r, const std::string& part) {
  for (const auto& w : r.warnings) {
    if (w.message.find(part) != std::string::npos) return true;
  }
  return false;
}

std::string all_warnings(const ReadResult& r) {
  std::string s;
  for (const auto& w : r.warnings) s += w.message + "\n";
  return s;
}

// Seconds at 120 bpm (the default) for a tick count at a given tpq.
double at120(double ticks, double tpq) { return ticks / tpq * 0.5; }

Events scale_track(int ch, int first_key, int count, int len = 96) {
  Events t;
  for (int i = 0; i < count; ++i) t.on(0, ch, first_key + i).off(static_cast<std::uint32_t>(len), ch, first_key + i);
  return t.end();
}

}  // namespace

// ---- formats and logical tracks ----

TEST(MidiReader, Format1TracksNotesAndTimes) {
  Events conductor;
  conductor.name(0, "Conductor").end();
  Events piano;
  piano.name(0, "Piano").on(0, 0, 60, 90).off(96, 0, 60).on(48, 0, 64, 80).off(48, 0, 64).end(24);
  const ReadResult r = read(smf(1, 96, {conductor, piano}));
  const auto& s = r.song;
  EXPECT_EQ(s.format, 1);
  ASSERT_EQ(s.tracks.size(), 2u);
  EXPECT_EQ(s.tracks[0].name, "Conductor");
  EXPECT_EQ(s.tracks[0].note_count, 0u);
  EXPECT_EQ(s.tracks[1].name, "Piano");
  ASSERT_EQ(s.notes.size(), 2u);
  const Note& a = s.notes[0];
  EXPECT_EQ(a.track, 1u);
  EXPECT_EQ(a.key, 60);
  EXPECT_EQ(a.velocity, 90);
  EXPECT_EQ(a.start_tick, 0u);
  EXPECT_EQ(a.end_tick, 96u);
  EXPECT_DOUBLE_EQ(s.end_s(a), at120(96, 96));
  const Note& b = s.notes[1];
  EXPECT_EQ(b.start_tick, 144u);
  EXPECT_EQ(b.end_tick, 192u);
  EXPECT_DOUBLE_EQ(s.start_s(b), at120(144, 96));
  EXPECT_EQ(s.tracks[1].key_min(), 60);
  EXPECT_EQ(s.tracks[1].key_max(), 64);
  EXPECT_EQ(s.tracks[1].distinct_keys(), 2);
  EXPECT_EQ(s.tracks[1].end_tick, 216u);
  EXPECT_EQ(s.end_tick, 216u);
  EXPECT_DOUBLE_EQ(s.duration_s(), at120(216, 96));
  EXPECT_TRUE(r.warnings.empty()) << all_warnings(r);
}

TEST(MidiReader, Format0IsSplitByChannelInOrderOfFirstNote) {
  Events t;
  t.name(0, "Song").program(0, 1, 40).on(0, 3, 50).on(0, 1, 70).on(0, 3, 52);
  t.off(96, 3, 50).off(0, 1, 70).off(0, 3, 52).on(0, 9, 36).off(10, 9, 36).end();
  const ReadResult r = read(smf(0, 96, {t}));
  const auto& s = r.song;
  ASSERT_EQ(s.tracks.size(), 3u);
  EXPECT_EQ(s.tracks[0].channels, 1u << 3);
  EXPECT_EQ(s.tracks[0].note_count, 2u);
  EXPECT_EQ(s.tracks[1].channels, 1u << 1);
  EXPECT_EQ(s.tracks[1].program(), 40);
  EXPECT_EQ(s.tracks[2].channels, 1u << 9);
  EXPECT_TRUE(s.tracks[2].is_drums());
  for (const auto& tr : s.tracks) {
    EXPECT_EQ(tr.chunk, 0u);
    EXPECT_EQ(tr.name, "Song");
  }
  for (const Note& n : s.notes) EXPECT_EQ(s.tracks[n.track].channels, 1u << n.channel);
}

TEST(MidiReader, Format0WithoutNotesHasOneEmptyTrack) {
  Events t;
  t.name(0, "Silence").end(480);
  const ReadResult r = read(smf(0, 96, {t}));
  ASSERT_EQ(r.song.tracks.size(), 1u);
  EXPECT_EQ(r.song.tracks[0].note_count, 0u);
  EXPECT_EQ(r.song.tracks[0].key_min(), -1);
  EXPECT_DOUBLE_EQ(r.song.duration_s(), 2.5);
}

TEST(MidiReader, Format2PatternsPlayInSequenceEachWithItsOwnTempo) {
  Events p1;
  p1.tempo(0, 1000000).on(0, 0, 60).off(96, 0, 60).end(96);  // 60 bpm: 2 s long
  Events p2;
  p2.on(0, 0, 62).off(96, 0, 62).end();  // default 120 bpm again
  Events p3;
  p3.tempo(0, 250000).on(48, 1, 64).off(96, 1, 64).end();  // 240 bpm
  const ReadResult r = read(smf(2, 96, {p1, p2, p3}));
  const auto& s = r.song;
  ASSERT_EQ(s.tracks.size(), 3u);
  ASSERT_EQ(s.notes.size(), 3u);
  EXPECT_EQ(s.notes[0].track, 0u);
  EXPECT_DOUBLE_EQ(s.end_s(s.notes[0]), 1.0);
  EXPECT_EQ(s.notes[1].start_tick, 192u);
  EXPECT_DOUBLE_EQ(s.start_s(s.notes[1]), 2.0);
  EXPECT_DOUBLE_EQ(s.end_s(s.notes[1]), 2.5);
  EXPECT_EQ(s.notes[2].track, 2u);
  EXPECT_EQ(s.notes[2].start_tick, 288u + 48u);
  EXPECT_DOUBLE_EQ(s.start_s(s.notes[2]), 2.5 + 0.125);
  EXPECT_DOUBLE_EQ(s.end_s(s.notes[2]), 2.5 + 0.125 + 0.25);
  EXPECT_DOUBLE_EQ(s.duration_s(), 2.875);
  EXPECT_EQ(s.tracks[1].end_us, 2500000);
}

TEST(MidiReader, UnknownFormatReadAsFormat1) {
  Bytes b = header(7, 1, 96);
  append(b, chunk("MTrk", scale_track(0, 60, 2).data));
  const ReadResult r = read(b);
  EXPECT_EQ(r.song.format, 1);
  EXPECT_EQ(r.song.notes.size(), 2u);
  EXPECT_TRUE(has_warning(r, "unknown format 7"));
}

// ---- chunks and container ----

TEST(MidiReader, UnknownChunksAreSkipped) {
  Bytes b = header(1, 1, 96);
  append(b, chunk("Junk", Bytes{'h', 'e', 'l', 'l', 'o', 0x90, 0x3C, 0x7F}));
  append(b, chunk("MTrk", scale_track(0, 60, 3).data));
  append(b, chunk("XYZW", Bytes(5, 0x90)));
  const ReadResult r = read(b);
  EXPECT_EQ(r.song.notes.size(), 3u);
  EXPECT_EQ(r.song.tracks.size(), 1u);
  EXPECT_TRUE(has_warning(r, "unknown chunk \"Junk\" (8 bytes) skipped"));
  EXPECT_TRUE(has_warning(r, "unknown chunk \"XYZW\""));
}

TEST(MidiReader, TrackCountInHeaderIsNotTrusted) {
  Bytes b = header(1, 1, 96);
  append(b, chunk("MTrk", scale_track(0, 60, 2).data));
  append(b, chunk("MTrk", scale_track(1, 70, 3).data));
  const ReadResult r = read(b);
  EXPECT_EQ(r.song.tracks.size(), 2u);
  EXPECT_EQ(r.song.notes.size(), 5u);
  EXPECT_TRUE(has_warning(r, "announces 1 tracks, the file has 2"));

  Bytes none = header(1, 0, 96);  // ntrks 0
  append(none, chunk("MTrk", scale_track(0, 60, 1).data));
  EXPECT_EQ(read(none).song.notes.size(), 1u);
}

TEST(MidiReader, LongerMThdIsHonoured) {
  Bytes b = header(1, 1, 96, 10);  // 4 extension bytes (zeros) must not be read as a chunk
  append(b, chunk("MTrk", scale_track(0, 60, 2).data));
  const ReadResult r = read(b);
  EXPECT_EQ(r.song.notes.size(), 2u);
  EXPECT_TRUE(r.warnings.empty()) << all_warnings(r);
}

TEST(MidiReader, ShortOrHugeMThdLengthIsReadAsSix) {
  Bytes b = header(1, 1, 96);
  b[7] = 4;  // MThd length 4, but 6 bytes of fields follow
  append(b, chunk("MTrk", scale_track(0, 60, 2).data));
  ReadResult r = read(b);
  EXPECT_EQ(r.song.notes.size(), 2u);
  EXPECT_TRUE(has_warning(r, "less than 6"));

  b[4] = 0x7F;  // absurd length past the end of the file
  r = read(b);
  EXPECT_EQ(r.song.notes.size(), 2u);
  EXPECT_TRUE(has_warning(r, "runs past the end; read as 6"));
}

TEST(MidiReader, TrailingGarbageIsIgnored) {
  Bytes b = smf(1, 96, {scale_track(0, 60, 4)});
  b.push_back(0x2A);  // one extra byte (jazz-soft test-corrupt-file-extra-byte)
  ReadResult r = read(b);
  EXPECT_EQ(r.song.notes.size(), 4u);
  EXPECT_TRUE(has_warning(r, "1 trailing bytes ignored"));

  for (int i = 0; i < 40; ++i) b.push_back(static_cast<std::uint8_t>(0x80 + i));  // binary junk
  r = read(b);
  EXPECT_EQ(r.song.notes.size(), 4u);
  EXPECT_TRUE(has_warning(r, "not a chunk ignored"));
}

TEST(MidiReader, RiffRmidIsUnwrapped) {
  const Bytes inner = smf(1, 96, {scale_track(0, 60, 5)});
  ReadResult r = read(rmid(inner));
  EXPECT_EQ(r.song.notes.size(), 5u);
  EXPECT_TRUE(r.warnings.empty()) << all_warnings(r);

  // An odd-sized sub-chunk (padded to even) before `data`.
  Bytes list{'L', 'I', 'S', 'T', 3, 0, 0, 0, 'a', 'b', 'c', 0};
  r = read(rmid(inner, list));
  EXPECT_EQ(r.song.notes.size(), 5u);

  // Offsets in messages count from the start of the RIFF file: RIFF header 12 + data header 8.
  Bytes bad = header(1, 1, 96);
  append(bad, chunk("MTrk", Bytes{0x00, 0x3C, 0x7F}));
  EXPECT_EQ(error_of(rmid(bad)), "track 0 at byte 0x2b: data byte without running status");

  Bytes wave{'R', 'I', 'F', 'F', 4, 0, 0, 0, 'W', 'A', 'V', 'E'};
  EXPECT_EQ(error_of(wave), "byte 0x8: not a MIDI file: RIFF form \"WAVE\"");
  Bytes no_data{'R', 'I', 'F', 'F', 4, 0, 0, 0, 'R', 'M', 'I', 'D'};
  EXPECT_EQ(error_of(no_data), "byte 0xc: RIFF RMID file without a data chunk");
}

TEST(MidiReader, NotMidiEmptyAndHeaderOnlyAreErrors) {
  EXPECT_EQ(error_of({}), "empty file (0 bytes)");
  const std::string text = "not a midi file";
  EXPECT_EQ(error_of(Bytes(text.begin(), text.end())), "byte 0x0: not a MIDI file: no MThd header");
  EXPECT_EQ(error_of(Bytes{'M', 'T', 'h', 'd', 0, 0, 0, 6, 0}), "byte 0x0: MThd header cut short");
  EXPECT_EQ(error_of(header(1, 1, 96)), "byte 0xe: no track (MTrk chunk) in the file");
  EXPECT_EQ(error_of(Bytes{0xF0, 0x7E, 0x7F, 0x06, 0x01, 0xF7}), "byte 0x0: not a MIDI file: no MThd header");
}

TEST(MidiReader, ShortPrefixBeforeMThdIsSkipped) {
  Bytes b(128, 0);  // e.g. a MacBinary header
  append(b, smf(1, 96, {scale_track(0, 60, 2)}));
  const ReadResult r = read(b);
  EXPECT_EQ(r.song.notes.size(), 2u);
  EXPECT_TRUE(has_warning(r, "128 bytes before the MThd header skipped"));
}

// ---- track lengths and truncation ----

TEST(MidiReader, DeclaredLengthPastEndOfFileIsClamped) {
  Bytes b = header(1, 1, 96);
  append(b, chunk("MTrk", scale_track(0, 60, 3).data, 0xFFFFFFFFll));
  const ReadResult r = read(b);
  EXPECT_EQ(r.song.notes.size(), 3u);
  EXPECT_TRUE(has_warning(r, "runs past the end of the file"));
}

TEST(MidiReader, MissingEndOfTrackLengthByte) {
  // jazz-soft test-corrupt-file-missing-byte: the file ends in "FF 2F" (no length byte).
  Bytes track = scale_track(0, 60, 8).data;
  track.pop_back();
  Bytes b = header(0, 1, 96);
  append(b, chunk("MTrk", track, static_cast<long long>(track.size()) + 1));
  const ReadResult r = read(b);
  EXPECT_EQ(r.song.notes.size(), 8u);
  EXPECT_DOUBLE_EQ(r.song.duration_s(), 4.0);
  EXPECT_TRUE(has_warning(r, "event cut off by the end of the file"));
}

TEST(MidiReader, TruncationMidEventKeepsEarlierEvents) {
  Events t;
  t.on(0, 0, 60).off(96, 0, 60).on(0, 0, 62).off(96, 0, 62).raw(0, {0x90, 0x40});  // velocity missing
  Bytes b = header(1, 1, 96);
  append(b, chunk("MTrk", t.data));
  const ReadResult r = read(b);
  ASSERT_EQ(r.song.notes.size(), 2u);
  EXPECT_EQ(r.song.tracks[0].end_tick, 192u);
  // Offset of the cut event: 22 + 4 events × 4 bytes = 38 = 0x26.
  EXPECT_TRUE(has_warning(r, "track 0 at byte 0x26: event cut off by the end of the track data")) << all_warnings(r);
}

TEST(MidiReader, TruncatedInsideDeltaOrSysexOrMeta) {
  for (const Bytes& tail : {Bytes{0x81}, Bytes{0x00, 0xF0, 0x05, 0x01}, Bytes{0x00, 0xFF, 0x01, 0x10, 'a'},
                            Bytes{0x00, 0xFF}, Bytes{0x00, 0xFF, 0x01, 0x8F}}) {
    Events t = scale_track(0, 60, 2);
    t.data.resize(t.data.size() - 4);  // drop End-of-Track
    t.data.insert(t.data.end(), tail.begin(), tail.end());
    Bytes b = header(1, 1, 96);
    append(b, chunk("MTrk", t.data));
    const ReadResult r = read(b);
    EXPECT_EQ(r.song.notes.size(), 2u);
    EXPECT_TRUE(has_warning(r, "cut off")) << all_warnings(r);
  }
}

TEST(MidiReader, TooShortDeclaredLengthStopsThereAndFindsNextTrack) {
  const Bytes full = scale_track(0, 60, 4).data;  // 4 notes × 8 bytes + EOT
  Bytes b = header(1, 2, 96);
  append(b, chunk("MTrk", full, 16));  // only the first two notes are inside the declared length
  append(b, chunk("MTrk", scale_track(1, 70, 1).data));
  const ReadResult r = read(b);
  ASSERT_EQ(r.song.tracks.size(), 2u);
  EXPECT_EQ(r.song.tracks[0].note_count, 2u);
  EXPECT_EQ(r.song.tracks[1].note_count, 1u);
  EXPECT_TRUE(has_warning(r, "no End-of-Track before the end of the track data"));
  EXPECT_TRUE(has_warning(r, "not a chunk skipped"));
}

TEST(MidiReader, TooLongDeclaredLengthStopsAtEndOfTrack) {
  const Bytes first = scale_track(0, 60, 2).data;
  const Bytes second = scale_track(1, 70, 3).data;
  Bytes b = header(1, 2, 96);
  append(b, chunk("MTrk", first, static_cast<long long>(first.size()) + 10));  // reaches into the next chunk
  append(b, chunk("MTrk", second));
  const ReadResult r = read(b);
  ASSERT_EQ(r.song.tracks.size(), 2u);
  EXPECT_EQ(r.song.tracks[0].note_count, 2u);
  EXPECT_EQ(r.song.tracks[1].note_count, 3u);
  EXPECT_TRUE(has_warning(r, "longer than the track"));

  // Padding after End-of-Track inside the declared length is skipped.
  Bytes padded = first;
  padded.insert(padded.end(), {0, 0, 0});
  Bytes c = header(1, 2, 96);
  append(c, chunk("MTrk", padded));
  append(c, chunk("MTrk", second));
  const ReadResult r2 = read(c);
  EXPECT_EQ(r2.song.notes.size(), 5u);
  EXPECT_TRUE(has_warning(r2, "3 bytes after End-of-Track ignored"));
}

TEST(MidiReader, MissingEndOfTrackEndsAtLastEvent) {
  Events t;
  t.on(0, 0, 60).off(96, 0, 60).on(0, 0, 62);  // no EOT, last note still on
  Bytes b = header(1, 1, 96);
  append(b, chunk("MTrk", t.data));
  const ReadResult r = read(b);
  ASSERT_EQ(r.song.notes.size(), 2u);
  EXPECT_EQ(r.song.notes[1].end_tick, 96u);  // ends where the track does
  EXPECT_TRUE(has_warning(r, "no End-of-Track"));
  EXPECT_TRUE(has_warning(r, "1 notes still sounding"));
}

// ---- running status, illegal bytes, sysex ----

TEST(MidiReader, RunningStatus) {
  Events t;
  t.on(0, 2, 60).bytes({0x60, 0x3C, 0x00, 0x00, 0x3E, 0x50, 0x60, 0x3E, 0x00}).end();
  const ReadResult r = read(smf(1, 96, {t}));
  ASSERT_EQ(r.song.notes.size(), 2u);
  EXPECT_EQ(r.song.notes[1].key, 0x3E);
  EXPECT_EQ(r.song.notes[1].velocity, 0x50);
  EXPECT_EQ(r.song.notes[1].channel, 2);
  EXPECT_EQ(r.song.notes[1].start_tick, 96u);
  EXPECT_EQ(r.song.notes[1].end_tick, 192u);
  EXPECT_TRUE(r.warnings.empty()) << all_warnings(r);
}

TEST(MidiReader, RunningStatusSurvivesMetaAndSysexWithWarning) {
  for (const Bytes& interruption :
       {Bytes{0xFF, 0x01, 0x05, 'b', 'r', 'e', 'a', 'k'}, Bytes{0xF0, 0x02, 0x7E, 0xF7}, Bytes{0xF7, 0x01, 0xF8}}) {
    Events t;
    t.on(0, 0, 60).bytes({0x60, 0x3C, 0x00});  // running status note-off
    t.bytes({0x00});
    t.data.insert(t.data.end(), interruption.begin(), interruption.end());
    t.bytes({0x00, 0x3E, 0x7F, 0x60, 0x3E, 0x00}).end();  // running status after the interruption
    const ReadResult r = read(smf(1, 96, {t}));
    EXPECT_EQ(r.song.notes.size(), 2u);
    EXPECT_TRUE(has_warning(r, "running status continues after a meta or sysex event")) << all_warnings(r);
  }
}

TEST(MidiReader, DataByteWithoutRunningStatusIsAnError) {
  // Nothing readable at all → BadInput naming track and byte.
  Events bad;
  bad.bytes({0x00, 0x3C, 0x7F}).end();
  EXPECT_EQ(error_of(smf(1, 96, {bad})), "track 0 at byte 0x17: data byte without running status");

  // Another track has notes → that track ends with a warning, the rest is kept.
  Events good = scale_track(0, 60, 3);
  const ReadResult r = read(smf(1, 96, {good, bad}));
  EXPECT_EQ(r.song.notes.size(), 3u);
  EXPECT_EQ(r.song.tracks.size(), 2u);
  EXPECT_TRUE(has_warning(r, "track 1 at byte"));
  EXPECT_TRUE(has_warning(r, "data byte without running status"));
}

TEST(MidiReader, ErrorMidTrackKeepsWhatCameBefore) {
  Events t;
  t.on(0, 0, 60).off(96, 0, 60).on(0, 0, 62).off(96, 0, 62).raw(0, {0xF4}).on(0, 0, 64).off(96, 0, 64).end();
  const ReadResult r = read(smf(1, 96, {t}));
  EXPECT_EQ(r.song.notes.size(), 2u);
  EXPECT_TRUE(has_warning(r, "track 0 at byte 0x27: illegal status byte 0xf4")) << all_warnings(r);
}

TEST(MidiReader, SystemBytesF1ToFEAreErrors) {
  for (int status = 0xF1; status <= 0xFE; ++status) {
    if (status == 0xF7) continue;  // F7 is the sysex escape, tested below
    Events t;
    t.raw(0, {static_cast<std::uint8_t>(status), 0x00}).on(0, 0, 60).off(96, 0, 60).end();
    char want[80];
    std::snprintf(want, sizeof want, "track 0 at byte 0x17: illegal status byte 0x%02x", status);
    EXPECT_EQ(error_of(smf(1, 96, {t})).rfind(want, 0), 0u) << error_of(smf(1, 96, {t}));
  }
}

TEST(MidiReader, StatusByteWhereDataBelongsIsAnError) {
  Events t;
  t.on(0, 0, 60).off(96, 0, 60).raw(0, {0x90, 0x3E, 0x90}).end();
  const ReadResult r = read(smf(1, 96, {t}));
  EXPECT_EQ(r.song.notes.size(), 1u);
  EXPECT_TRUE(has_warning(r, "status byte 0x90 where a data byte belongs"));
}

TEST(MidiReader, SysexAndEscapeBytesAreSkippedNotParsed) {
  Events t;
  t.raw(0, {0xF0, 0x05, 0x90, 0x3C, 0x7F, 0x00, 0xF7});  // sysex whose data looks like a note-on
  t.raw(0, {0xF7, 0x03, 0x90, 0x40, 0x7F});              // F7 escape with a "note-on" inside
  t.raw(0, {0xF7, 0x00});                                // empty escape
  t.on(0, 0, 67).off(96, 0, 67).end();
  const ReadResult r = read(smf(1, 96, {t}));
  ASSERT_EQ(r.song.notes.size(), 1u);
  EXPECT_EQ(r.song.notes[0].key, 67);
  EXPECT_TRUE(r.warnings.empty()) << all_warnings(r);
}

// ---- VLQ and ticks ----

TEST(MidiReader, FourByteVlqIsTheMaximum) {
  Events t;
  t.on(0x0FFFFFFF, 0, 60).off(1, 0, 60).end();
  const ReadResult r = read(smf(1, 96, {t}));
  ASSERT_EQ(r.song.notes.size(), 1u);
  EXPECT_EQ(r.song.notes[0].start_tick, 0x0FFFFFFFu);
  EXPECT_NEAR(r.song.start_s(r.song.notes[0]), at120(268435455.0, 96), 1e-6);
}

TEST(MidiReader, FiveByteVlqIsAnError) {
  Events t;
  t.on(0, 0, 60).off(96, 0, 60).bytes({0x81, 0x80, 0x80, 0x80, 0x00, 0x90, 0x3C, 0x40}).end();
  const ReadResult r = read(smf(1, 96, {t}));
  EXPECT_EQ(r.song.notes.size(), 1u);
  EXPECT_TRUE(has_warning(r, "track 0 at byte 0x1e: variable-length quantity longer than 4 bytes")) << all_warnings(r);
  // Also in a meta length.
  Events m;
  m.on(0, 0, 60).off(96, 0, 60).bytes({0x00, 0xFF, 0x01, 0xFF, 0xFF, 0xFF, 0xFF, 0x01}).end();
  EXPECT_TRUE(has_warning(read(smf(1, 96, {m})), "longer than 4 bytes"));
}

TEST(MidiReader, AbsoluteTicksBeyond32Bits) {
  Events t;
  for (int i = 0; i < 20; ++i) t.meta(0x0FFFFFFF, 0x01, {'x'});
  t.on(5, 0, 60).off(10, 0, 60).end();
  const ReadResult r = read(smf(1, 480, {t}));
  ASSERT_EQ(r.song.notes.size(), 1u);
  const std::uint64_t start = 20ull * 0x0FFFFFFF + 5;
  EXPECT_GT(start, 0xFFFFFFFFull);
  EXPECT_EQ(r.song.notes[0].start_tick, start);
  EXPECT_EQ(r.song.notes[0].end_tick, start + 10);
  EXPECT_NEAR(r.song.start_s(r.song.notes[0]), at120(static_cast<double>(start), 480), 1e-6);
}

// ---- note pairing ----

TEST(MidiReader, VelocityZeroIsNoteOff) {
  Events t;
  t.on(0, 0, 60).on(48, 0, 60, 0).end();
  const ReadResult r = read(smf(1, 96, {t}));
  ASSERT_EQ(r.song.notes.size(), 1u);
  EXPECT_EQ(r.song.notes[0].end_tick, 48u);
}

TEST(MidiReader, OverlappingSameKeyNotesPairFirstInFirstOut) {
  Events t;
  t.on(0, 0, 60, 10).on(10, 0, 60, 20).off(10, 0, 60).off(10, 0, 60).end();
  const ReadResult r = read(smf(1, 96, {t}));
  ASSERT_EQ(r.song.notes.size(), 2u);
  EXPECT_EQ(r.song.notes[0].velocity, 10);
  EXPECT_EQ(r.song.notes[0].start_tick, 0u);
  EXPECT_EQ(r.song.notes[0].end_tick, 20u);
  EXPECT_EQ(r.song.notes[1].velocity, 20);
  EXPECT_EQ(r.song.notes[1].start_tick, 10u);
  EXPECT_EQ(r.song.notes[1].end_tick, 30u);
}

TEST(MidiReader, PairingIsPerChannelAndPerTrack) {
  Events a;
  a.on(0, 0, 60).on(0, 1, 60).off(10, 1, 60).off(10, 0, 60).end();
  Events b;
  b.off(5, 0, 60).end();  // another track cannot end track 0's note
  const ReadResult r = read(smf(1, 96, {a, b}));
  ASSERT_EQ(r.song.notes.size(), 2u);
  EXPECT_EQ(r.song.notes[0].channel, 0);
  EXPECT_EQ(r.song.notes[0].end_tick, 20u);
  EXPECT_EQ(r.song.notes[1].channel, 1);
  EXPECT_EQ(r.song.notes[1].end_tick, 10u);
  EXPECT_TRUE(has_warning(r, "track 1 at byte"));
  EXPECT_TRUE(has_warning(r, "note-off without a sounding note"));
}

TEST(MidiReader, AtOneTickTheOldNoteEndsBeforeTheNewOneStarts) {
  // Re-struck key: at tick 96 the file lists the new note-on before the note-off.
  Events t;
  t.on(0, 0, 60).on(96, 0, 60).off(0, 0, 60).off(96, 0, 60).end();
  const ReadResult r = read(smf(1, 96, {t}));
  ASSERT_EQ(r.song.notes.size(), 2u);
  EXPECT_EQ(r.song.notes[0].start_tick, 0u);
  EXPECT_EQ(r.song.notes[0].end_tick, 96u);
  EXPECT_EQ(r.song.notes[1].start_tick, 96u);
  EXPECT_EQ(r.song.notes[1].end_tick, 192u);
}

TEST(MidiReader, ZeroLengthNotesAreKept) {
  Events t;
  t.on(50, 0, 60).off(0, 0, 60).on(0, 0, 60).off(50, 0, 60).end();  // music21 test16's pattern
  const ReadResult r = read(smf(1, 96, {t}));
  ASSERT_EQ(r.song.notes.size(), 2u);
  EXPECT_EQ(r.song.notes[0].start_tick, 50u);
  EXPECT_EQ(r.song.notes[0].end_tick, 50u);
  EXPECT_EQ(r.song.start_us(r.song.notes[0]), r.song.end_us(r.song.notes[0]));
  EXPECT_EQ(r.song.notes[1].end_tick, 100u);
}

TEST(MidiReader, RandomPairingMatchesAFifoReference) {
  // Sounding notes are chained through their end_tick (smf_detail.hpp): deep FIFOs of re-struck keys,
  // FIFOs emptied and refilled, orphan note-offs, notes left sounding at the end of a track, and ticks
  // beyond 2^32 (whose low bits could pass for a note index) must pair exactly as a plain per-(track,
  // channel, key) queue of note-ons does.
  std::mt19937 rng(20240611);
  struct Want {
    std::uint64_t start = 0, end = 0;
    std::uint32_t track = 0;
    int channel = 0, key = 0, velocity = 0;
  };
  for (int round = 0; round < 20; ++round) {
    SCOPED_TRACE(round);
    std::vector<Events> tracks(3);
    std::vector<Want> want;
    for (std::uint32_t track = 0; track < tracks.size(); ++track) {
      std::map<std::pair<int, int>, std::deque<std::size_t>> sounding;
      std::uint64_t tick = 0;
      for (int e = 0; e < 16; ++e) tracks[track].meta(0x0FFFFFFF, 0x01, {'x'});  // to 2^32 − 16
      tick += 16ull * 0x0FFFFFFF;
      for (int e = 0; e < 300; ++e) {
        const std::uint32_t delta = rng() % 50 == 0 ? 0x0FFFFFFFu : static_cast<std::uint32_t>(rng() % 4);
        tick += delta;
        const int channel = static_cast<int>(rng() % 2), key = 60 + static_cast<int>(rng() % 3);
        if (rng() % 100 < 55) {
          const int velocity = 1 + static_cast<int>(rng() % 127);
          tracks[track].on(delta, channel, key, velocity);
          sounding[{channel, key}].push_back(want.size());
          want.push_back(Want{tick, 0, track, channel, key, velocity});
        } else {
          tracks[track].off(delta, channel, key);  // an orphan when nothing sounds: ignored
          auto& queue = sounding[{channel, key}];
          if (!queue.empty()) {
            want[queue.front()].end = tick;
            queue.pop_front();
          }
        }
      }
      EXPECT_GT(tick, 0xFFFFFFFFull);
      tracks[track].end(7);
      for (auto& [where, queue] : sounding) {
        for (const std::size_t i : queue) want[i].end = tick + 7;  // ended by End-of-Track
      }
    }
    const ReadResult r = read(smf(1, 96, tracks));
    ASSERT_EQ(r.song.notes.size(), want.size());
    for (std::size_t i = 0; i < want.size(); ++i) {
      const Note& n = r.song.notes[i];
      SCOPED_TRACE(i);
      EXPECT_EQ(n.track, want[i].track);
      EXPECT_EQ(n.channel, want[i].channel);
      EXPECT_EQ(n.key, want[i].key);
      EXPECT_EQ(n.velocity, want[i].velocity);
      EXPECT_EQ(n.start_tick, want[i].start);
      EXPECT_EQ(n.end_tick, want[i].end);
    }
  }
}

TEST(MidiReader, NotesStillOnEndAtEndOfTrack) {
  Events t;
  t.on(0, 0, 60).on(10, 0, 64).end(200);
  const ReadResult r = read(smf(1, 96, {t}));
  ASSERT_EQ(r.song.notes.size(), 2u);
  EXPECT_EQ(r.song.notes[0].end_tick, 210u);
  EXPECT_EQ(r.song.notes[1].end_tick, 210u);
  EXPECT_TRUE(has_warning(r, "2 notes still sounding at the end of the track"));
}

// ---- tempo, time signature, SMPTE ----

TEST(MidiReader, TempoInANonFirstTrackIsGlobal) {
  Events notes;
  notes.on(0, 0, 60).off(96, 0, 60).on(0, 0, 62).off(96, 0, 62).on(0, 0, 64).off(96, 0, 64).end();
  Events tempo_track;
  tempo_track.tempo(96, 1000000).tempo(96, 250000).end();
  const ReadResult r = read(smf(1, 96, {notes, tempo_track}));
  ASSERT_EQ(r.song.notes.size(), 3u);
  // 0–96 at 120 bpm (0.5 s), 96–192 at 60 bpm (1 s), 192–288 at 240 bpm (0.25 s).
  EXPECT_DOUBLE_EQ(r.song.start_s(r.song.notes[1]), 0.5);
  EXPECT_DOUBLE_EQ(r.song.end_s(r.song.notes[1]), 1.5);
  EXPECT_DOUBLE_EQ(r.song.end_s(r.song.notes[2]), 1.75);
  ASSERT_EQ(r.song.tempo_changes.size(), 3u);
  EXPECT_DOUBLE_EQ(r.song.tempo_changes[0].bpm(), 120.0);
  EXPECT_EQ(r.song.tempo_changes[1].tick, 96u);
  EXPECT_DOUBLE_EQ(r.song.tempo_changes[1].bpm(), 60.0);
  EXPECT_EQ(r.song.tempo_changes[2].us, 1500000);
}

TEST(MidiReader, MalformedTempoIsIgnored) {
  Events t;
  t.meta(0, 0x51, {0x00, 0x00, 0x00}).meta(0, 0x51, {0x07}).on(0, 0, 60).off(96, 0, 60).end();
  const ReadResult r = read(smf(1, 96, {t}));
  EXPECT_DOUBLE_EQ(r.song.end_s(r.song.notes[0]), 0.5);
  EXPECT_TRUE(has_warning(r, "malformed tempo or time signature event ignored (2 times)"));
}

TEST(MidiReader, TimeSignaturesAreCollected) {
  Events a;
  a.meta(0, 0x58, {3, 2, 24, 8}).end();
  Events b;
  b.meta(192, 0x58, {6, 3, 36, 8}).on(0, 0, 60).off(10, 0, 60).end();
  const ReadResult r = read(smf(1, 96, {a, b}));
  ASSERT_EQ(r.song.time_signatures.size(), 2u);
  EXPECT_EQ(r.song.time_signatures[0].numerator, 3);
  EXPECT_EQ(r.song.time_signatures[1].tick, 192u);
  EXPECT_EQ(r.song.time_signatures[1].denominator_log2, 3);
  EXPECT_EQ(r.song.time_signatures[1].us, 1000000);
}

TEST(MidiReader, SmpteDivisionIgnoresTempo) {
  Events t;
  t.tempo(0, 1000000).on(0, 0, 60).off(1000, 0, 60).end();
  // 25 fps × 40 ticks per frame: 1 ms per tick.
  Bytes b = header(1, 1, 0xE728);
  append(b, chunk("MTrk", t.data));
  ReadResult r = read(b);
  ASSERT_EQ(r.song.notes.size(), 1u);
  EXPECT_TRUE(r.song.division.smpte);
  EXPECT_DOUBLE_EQ(r.song.end_s(r.song.notes[0]), 1.0);
  EXPECT_TRUE(r.song.tempo_changes.empty());

  // 29.97 fps × 4 ticks: tick n at n·1001/(30000·4) s.
  Bytes c = header(1, 1, 0xE304);
  append(c, chunk("MTrk", t.data));
  r = read(c);
  EXPECT_EQ(r.song.division.fps, 29);
  EXPECT_NEAR(r.song.end_s(r.song.notes[0]), 1000.0 * 1001.0 / 120000.0, 1e-6);
  EXPECT_TRUE(r.warnings.empty()) << all_warnings(r);

  // 123 fps (high byte 0x85) is no SMPTE rate: read as given, with a warning.
  Bytes d = header(1, 1, 0x8501);
  append(d, chunk("MTrk", t.data));
  r = read(d);
  EXPECT_EQ(r.song.division.fps, 123);
  EXPECT_NE(all_warnings(r).find("SMPTE division of 123 frames a second"), std::string::npos) << all_warnings(r);
}

// ---- programs ----

TEST(MidiReader, ProgramIsTheChannelsProgramAtNoteStart) {
  Events conductor;
  conductor.program(0, 0, 73).program(200, 0, 40).end();  // channel 0: flute, then violin at tick 200
  Events player;
  player.on(0, 0, 60).off(100, 0, 60);                   // starts at 0: flute
  player.on(100, 0, 62).off(100, 0, 62);                 // starts at 200 (same tick as the change): violin
  player.on(0, 1, 50).off(10, 1, 50);                    // channel 1 never set: 0
  player.program(0, 1, 42).on(0, 1, 52).off(10, 1, 52);  // set just before: cello
  player.end();
  const ReadResult r = read(smf(1, 96, {conductor, player}));
  ASSERT_EQ(r.song.notes.size(), 4u);
  EXPECT_EQ(r.song.notes[0].program, 73);
  EXPECT_EQ(r.song.notes[1].program, 40);
  EXPECT_EQ(r.song.notes[2].program, 0);
  EXPECT_EQ(r.song.notes[3].program, 42);
  const auto& uses = r.song.tracks[1].programs;
  ASSERT_EQ(uses.size(), 4u);
  EXPECT_EQ(uses[0].program, 73);
  EXPECT_EQ(uses[0].notes, 1u);
  EXPECT_EQ(r.song.tracks[1].program(), 73);
  EXPECT_EQ(r.song.tracks[1].channels, 0b11u);
}

// ---- names and hostile lengths ----

TEST(MidiReader, NamesBecomeValidUtf8) {
  Events latin1;
  latin1.meta(0, 0x03, {'C', 'a', 'f', 0xE9, ' ', 0x00}).end();
  Events utf8;
  utf8.meta(0, 0x03, {'C', 'a', 'f', 0xC3, 0xA9}).end();
  Events instrument;
  instrument.meta(0, 0x04, {'O', 'b', 'o', 'e'}).end();
  const ReadResult r = read(smf(1, 96, {latin1, utf8, instrument}));
  EXPECT_EQ(r.song.tracks[0].name, "Caf\xC3\xA9");
  EXPECT_EQ(r.song.tracks[1].name, "Caf\xC3\xA9");
  EXPECT_EQ(r.song.tracks[2].name, "Oboe");
}

TEST(MidiReader, HugeDeclaredLengthsDoNotAllocateOrHang) {
  for (const Bytes& tail : {Bytes{0x00, 0xFF, 0x01, 0xFF, 0xFF, 0xFF, 0x7F},  // meta of 256 MB
                            Bytes{0x00, 0xF0, 0xFF, 0xFF, 0xFF, 0x7F},        // sysex of 256 MB
                            Bytes{0x00, 0xF7, 0xFF, 0xFF, 0xFF, 0x7F}}) {
    Events t = scale_track(0, 60, 1);
    t.data.resize(t.data.size() - 4);
    t.data.insert(t.data.end(), tail.begin(), tail.end());
    const ReadResult r = read(smf(1, 96, {t}));
    EXPECT_EQ(r.song.notes.size(), 1u);
  }
  Bytes b = header(1, 1, 96);
  append(b, chunk("Huge", Bytes{1, 2, 3}, 0xFFFFFFF0ll));
  append(b, chunk("MTrk", scale_track(0, 60, 1).data));  // swallowed by the huge unknown chunk
  EXPECT_EQ(error_of(b), "byte 0xe: no track (MTrk chunk) in the file");
}

TEST(MidiReader, WarningsStayBounded) {
  Bytes b = header(1, 1, 96);
  for (int i = 0; i < 1000; ++i) append(b, chunk("Junk", {}));
  append(b, chunk("MTrk", scale_track(0, 60, 1).data));
  const ReadResult r = read(b);
  EXPECT_EQ(r.song.notes.size(), 1u);
  EXPECT_LE(r.warnings.size(), hmp::midi::detail::WarningLog::kMaxWarnings + 1);
  EXPECT_NE(r.warnings.back().message.find("more warnings not shown"), std::string::npos);
}
