// The view's note index (host/view/note_index.hpp) against a brute-force scan of every note, on random
// songs with tempo changes, zero-length notes, notes of minutes and empty tracks: the visible bars are
// exactly those that overlap the window, at the times an independent tick → µs formula gives; sounding
// state follows the time alone. And the frame's work does not grow with the song.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "host/view/note_index.hpp"

namespace {

using hmp::view::Bar;
using hmp::view::NoteIndex;

// 500 ticks per quarter at 120 bpm (1 tick = 1 ms) until tick 10,000, then 240 bpm (1 tick = 0.5 ms).
constexpr std::uint64_t kChangeTick = 10'000;
std::int64_t reference_us(std::uint64_t tick) {
  return tick < kChangeTick ? static_cast<std::int64_t>(tick) * 1000
                            : 10'000'000 + static_cast<std::int64_t>(tick - kChangeTick) * 500;
}

hmp::midi::Song random_song(std::uint32_t tracks, std::size_t notes, unsigned seed) {
  hmp::midi::Song song;
  song.tempo_map = hmp::midi::TempoMap::metrical(500, {{kChangeTick, 250'000}});
  song.tracks.resize(tracks + 1);  // the last track stays empty
  for (std::uint32_t t = 0; t <= tracks; ++t) song.tracks[t].index = t;
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::uint64_t> start(0, 40'000);
  std::uniform_int_distribution<int> kind(0, 9);
  for (std::size_t i = 0; i < notes; ++i) {
    hmp::midi::Note n;
    n.track = static_cast<std::uint32_t>(rng() % tracks);
    n.start_tick = start(rng);
    const int k = kind(rng);
    const std::uint64_t length = k == 0 ? 0 : k == 1 ? 120'000 : rng() % 2000;  // zero, minutes, short
    n.end_tick = n.start_tick + length;
    n.key = static_cast<std::uint8_t>(21 + rng() % 88);
    n.velocity = 64;
    song.notes.push_back(n);
  }
  return song;
}

TEST(ViewNoteIndex, VisibleBarsAreExactlyThoseOverlappingTheWindow) {
  const hmp::midi::Song song = random_song(4, 3000, 7);
  const NoteIndex index(song);
  std::mt19937 rng(11);
  std::vector<Bar> got;
  int windows = 0, nonempty = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const std::int64_t t0 = static_cast<std::int64_t>(rng() % 60'000'000) - 1'000'000;
    const std::int64_t t1 = t0 + 1 + static_cast<std::int64_t>(rng() % 15'000'000);
    for (std::uint32_t track = 0; track <= 4; ++track) {
      index.visible(track, t0, t1, got);
      std::vector<std::pair<std::int64_t, int>> want;
      for (const hmp::midi::Note& n : song.notes) {
        if (n.track != track) continue;
        const std::int64_t s = reference_us(n.start_tick), e = reference_us(n.end_tick);
        const bool overlaps = s < t1 && (e > t0 || (e == s && s >= t0));
        if (overlaps) want.emplace_back(s, n.key);
      }
      std::vector<std::pair<std::int64_t, int>> have;
      for (const Bar& b : got) {
        EXPECT_EQ(b.track, track);
        have.emplace_back(b.start_us, b.key);
      }
      std::sort(want.begin(), want.end());
      std::sort(have.begin(), have.end());
      ASSERT_EQ(have, want) << "track " << track << " window [" << t0 << ", " << t1 << ")";
      ++windows;
      nonempty += !want.empty();
    }
  }
  EXPECT_GT(nonempty, windows / 2) << "the windows must mostly hold notes for the test to mean anything";
}

TEST(ViewNoteIndex, TimesFollowTheTempoMapAndSoundingFollowsTheTime) {
  const hmp::midi::Song song = random_song(2, 500, 3);
  const NoteIndex index(song);
  for (std::uint32_t track = 0; track < 2; ++track) {
    for (const Bar& b : index.bars(track)) {
      EXPECT_LE(b.start_us, b.end_us);
      EXPECT_FALSE(NoteIndex::sounding(b, b.start_us - 1));
      EXPECT_EQ(NoteIndex::sounding(b, b.start_us), b.end_us > b.start_us);
      EXPECT_FALSE(NoteIndex::sounding(b, b.end_us));
    }
  }
  // Every bar's times are the reference formula's for some note of its track.
  for (const hmp::midi::Note& n : song.notes) {
    const auto bars = index.bars(n.track);
    EXPECT_TRUE(std::any_of(bars.begin(), bars.end(), [&](const Bar& b) {
      return b.start_us == reference_us(n.start_tick) && b.end_us == reference_us(n.end_tick) && b.key == n.key;
    }));
  }
}

TEST(ViewNoteIndex, DegenerateInputs) {
  hmp::midi::Song empty;
  const NoteIndex none(empty);
  std::vector<Bar> out{Bar{}};
  EXPECT_EQ(none.visible(0, 0, 1'000'000, out), 0u);
  EXPECT_TRUE(out.empty());
  const hmp::midi::Song song = random_song(1, 100, 5);
  const NoteIndex index(song);
  EXPECT_EQ(index.visible(0, 5'000'000, 5'000'000, out), 0u) << "an empty window";
  EXPECT_EQ(index.visible(0, 9'000'000, 1'000'000, out), 0u) << "a reversed window";
  EXPECT_EQ(index.visible(7, 0, 60'000'000, out), 0u) << "no such track";
  EXPECT_EQ(index.visible(0, INT64_MIN / 2, INT64_MAX / 2, out), index.bars(0).size()) << "everything";
}

// The work of a frame is the bars it shows: a song 100 times longer with the same density finds the same
// number of bars in a window of the same length (the search is a binary search: log n, not n).
TEST(ViewNoteIndex, WorkPerWindowDoesNotGrowWithTheSong) {
  auto dense = [](std::size_t seconds) {
    hmp::midi::Song song;
    song.tempo_map = hmp::midi::TempoMap::metrical(500, {});  // 1 tick = 1 ms
    song.tracks.resize(1);
    for (std::size_t ms = 0; ms < seconds * 1000; ms += 100) {
      hmp::midi::Note n;
      n.start_tick = ms;
      n.end_tick = ms + 150;
      n.key = 60;
      song.notes.push_back(n);
    }
    return song;
  };
  const hmp::midi::Song small = dense(60), big = dense(6000);
  const NoteIndex a(small), b(big);
  std::vector<Bar> out;
  EXPECT_EQ(a.visible(0, 30'000'000, 42'000'000, out), b.visible(0, 3'000'000'000, 3'012'000'000, out));
  EXPECT_EQ(out.size(), 121u);  // starts in (29.85 s, 42 s): 121 notes of 150 ms every 100 ms
}

}  // namespace
