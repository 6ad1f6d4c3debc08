// Song notes → synthesizer events: time order (offs before ons at equal times), one note-off per run of
// overlapping same-key notes, programs carried by each note-on, zero-length and out-of-range values.
// Expected lists are written out by hand from the MIDI semantics, not taken from a run.
#include <gtest/gtest.h>

#include <vector>

#include "host/audio/audio_events.hpp"

namespace {

using hmp::audio::AudioEvent;
using Kind = AudioEvent::Kind;

// 1000 ticks per quarter at 1000 µs per quarter: one tick is one µs, so the notes' ticks below read as µs.
const hmp::midi::TempoMap kOneTickPerUs = hmp::midi::TempoMap::metrical(1000, {{0, 1000}});

std::vector<AudioEvent> audio_events(const std::vector<hmp::midi::Note>& notes) {
  return hmp::audio::audio_events(notes, kOneTickPerUs);
}

hmp::midi::Note note(std::uint64_t start_tick, std::uint64_t end_tick, std::uint8_t channel, std::uint8_t key,
                     std::uint8_t velocity = 100, std::uint8_t program = 0) {
  hmp::midi::Note n;
  n.start_tick = start_tick;
  n.end_tick = end_tick;
  n.channel = channel;
  n.key = key;
  n.velocity = velocity;
  n.program = program;
  return n;
}

AudioEvent on(std::int64_t t, std::uint8_t ch, std::uint8_t key, std::uint8_t vel, std::uint8_t program) {
  return {t, Kind::note_on, ch, key, vel, program};
}
AudioEvent off(std::int64_t t, std::uint8_t ch, std::uint8_t key) { return {t, Kind::note_off, ch, key, 0, 0}; }

TEST(AudioEvents, SortedWithOffsBeforeOnsAtEqualTimes) {
  // Given in file order per track (two tracks interleaved in time), a repeated key back to back.
  const std::vector<hmp::midi::Note> notes = {
      note(0, 500, 0, 60, 90, 0), note(500, 1000, 0, 60, 80, 0),  // same key re-struck at 500
      note(250, 750, 1, 64, 70, 40),                              // violin on channel 2
  };
  const std::vector<AudioEvent> want = {
      on(0, 0, 60, 90, 0),   on(250, 1, 64, 70, 40), off(500, 0, 60),
      on(500, 0, 60, 80, 0), off(750, 1, 64),        off(1000, 0, 60),
  };
  EXPECT_EQ(audio_events(notes), want);
}

TEST(AudioEvents, OverlappingSameKeyNotesSoundUntilTheLastEnds) {
  // Key 62 held 0–1000 and struck again 200–400 on the same channel: a synthesizer's note-off releases
  // every voice of the key, so the only note-off is at 1000.
  const std::vector<hmp::midi::Note> notes = {note(0, 1000, 3, 62), note(200, 400, 3, 62)};
  const std::vector<AudioEvent> want = {on(0, 3, 62, 100, 0), on(200, 3, 62, 100, 0), off(1000, 3, 62)};
  EXPECT_EQ(audio_events(notes), want);
  // The same key on another channel is independent.
  const std::vector<hmp::midi::Note> two_channels = {note(0, 1000, 3, 62), note(200, 400, 4, 62)};
  const std::vector<AudioEvent> want2 = {on(0, 3, 62, 100, 0), on(200, 4, 62, 100, 0), off(400, 4, 62),
                                         off(1000, 3, 62)};
  EXPECT_EQ(audio_events(two_channels), want2);
}

TEST(AudioEvents, ZeroLengthNotesGetAnOffJustAfter) {
  const std::vector<hmp::midi::Note> notes = {note(100, 100, 9, 38, 127, 0)};
  const std::vector<AudioEvent> want = {on(100, 9, 38, 127, 0), off(101, 9, 38)};
  EXPECT_EQ(audio_events(notes), want);
}

TEST(AudioEvents, ProgramsTravelWithTheirNotes) {
  // A channel switching program between two notes (program change in the file between them).
  const std::vector<hmp::midi::Note> notes = {note(0, 100, 0, 60, 100, 0), note(100, 200, 0, 60, 100, 24)};
  const auto ev = audio_events(notes);
  ASSERT_EQ(ev.size(), 4u);
  EXPECT_EQ(ev[0].program, 0);
  EXPECT_EQ(ev[2].kind, Kind::note_on);
  EXPECT_EQ(ev[2].program, 24);
}

TEST(AudioEvents, TimesComeFromTheTempoMap) {
  // 96 ticks per quarter, 120 bpm until tick 96, then 60 bpm: tick 48 is at 0.25 s, tick 144 at
  // 0.5 s + 48/96 × 1 s = 1 s. Two notes given out of time order, as two tracks' notes come.
  const hmp::midi::TempoMap map = hmp::midi::TempoMap::metrical(96, {{96, 1'000'000}});
  const std::vector<hmp::midi::Note> notes = {note(144, 192, 0, 64), note(48, 144, 1, 60)};
  const std::vector<AudioEvent> want = {on(250'000, 1, 60, 100, 0), off(1'000'000, 1, 60), on(1'000'000, 0, 64, 100, 0),
                                        off(1'500'000, 0, 64)};
  EXPECT_EQ(hmp::audio::audio_events(notes, map), want);
  // The Song overload uses the song's own map.
  hmp::midi::Song song;
  song.notes = notes;
  song.tempo_map = map;
  EXPECT_EQ(hmp::audio::audio_events(song), want);
}

TEST(AudioEvents, EmptySongAndClampedValues) {
  EXPECT_TRUE(audio_events(std::vector<hmp::midi::Note>{}).empty());
  // Velocity 0 cannot be a note-on (it would be a note-off): clamped to 1.
  const auto ev = audio_events(std::vector<hmp::midi::Note>{note(0, 10, 0, 60, 0, 0)});
  ASSERT_EQ(ev.size(), 2u);
  EXPECT_EQ(ev[0].velocity, 1);
}

}  // namespace
