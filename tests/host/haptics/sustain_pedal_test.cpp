// --pedal (sustain_pedal.hpp) against a brute-force reference written here: for each note, walk the ticks
// from its release replaying every sustain-pedal event up to that tick, and stop at the first tick where
// the pedal is up, the same key starts again on the channel, or the song ends. Random songs (notes,
// pedal presses and lifts, resets, several channels) and the edge cases by name.
#include <gtest/gtest.h>

#include <random>

#include "host/haptics/haptic_track.hpp"
#include "host/haptics/sustain_pedal.hpp"

namespace {

using namespace hmp;

midi::Note note(std::uint8_t channel, std::uint8_t key, std::uint64_t start, std::uint64_t end) {
  midi::Note n;
  n.channel = channel;
  n.key = key;
  n.start_tick = start;
  n.end_tick = end;
  n.velocity = 80;
  return n;
}

midi::Control cc(std::uint64_t tick, std::uint8_t channel, std::uint8_t number, std::uint16_t value) {
  return {tick, midi::Control::Kind::controller, channel, number, value};
}

std::uint64_t brute_force_end(const midi::Song& song, const std::vector<midi::Note>& notes, const midi::Note& n) {
  auto pedal_down_at = [&](std::uint64_t tick) {  // after every event at or before `tick`
    bool down = false;
    for (const midi::Control& c : song.controls) {
      if (c.tick > tick) break;
      if (c.channel != n.channel || c.kind != midi::Control::Kind::controller) continue;
      if (c.number == 64) down = c.value >= 64;
      if (c.number == 121) down = false;
    }
    return down;
  };
  auto restruck_at = [&](std::uint64_t tick) {
    for (const midi::Note& o : notes) {
      if (o.channel == n.channel && o.key == n.key && o.start_tick > n.start_tick && o.start_tick == tick) return true;
    }
    return false;
  };
  if (!pedal_down_at(n.end_tick)) return n.end_tick;
  std::uint64_t t = n.end_tick;
  while (t < song.end_tick && pedal_down_at(t) && !restruck_at(t)) ++t;
  return t;
}

TEST(SustainPedal, RandomSongsMatchTheTickByTickReference) {
  std::mt19937 rng(2026);
  for (int round = 0; round < 200; ++round) {
    midi::Song song;
    std::vector<midi::Note> notes;
    const int n_notes = 1 + static_cast<int>(rng() % 12);
    for (int i = 0; i < n_notes; ++i) {
      const std::uint64_t start = rng() % 300;
      notes.push_back(note(static_cast<std::uint8_t>(rng() % 2), static_cast<std::uint8_t>(60 + rng() % 3), start,
                           start + 1 + rng() % 80));
    }
    for (int i = 0, n = static_cast<int>(rng() % 10); i < n; ++i) {
      const auto ch = static_cast<std::uint8_t>(rng() % 2);
      const std::uint64_t tick = rng() % 400;
      if (rng() % 8 == 0) {
        song.controls.push_back(cc(tick, ch, 121, 0));
      } else {
        song.controls.push_back(cc(tick, ch, 64, static_cast<std::uint16_t>(rng() % 128)));
      }
    }
    std::stable_sort(song.controls.begin(), song.controls.end(),
                     [](const auto& a, const auto& b) { return a.tick < b.tick; });
    song.end_tick = 0;
    for (const midi::Note& n : notes) song.end_tick = std::max(song.end_tick, n.end_tick);
    song.end_tick += rng() % 50;
    const std::vector<std::uint64_t> ends = haptics::pedal_end_ticks(song, notes);
    ASSERT_EQ(ends.size(), notes.size());
    for (std::size_t i = 0; i < notes.size(); ++i) {
      EXPECT_EQ(ends[i], brute_force_end(song, notes, notes[i])) << "round " << round << " note " << i;
    }
  }
}

TEST(SustainPedal, TheNamedCases) {
  midi::Song song;
  song.end_tick = 1000;
  song.controls = {cc(100, 0, 64, 127), cc(500, 0, 64, 0), cc(600, 0, 64, 64), cc(700, 0, 121, 0), cc(800, 0, 64, 100)};
  const std::vector<midi::Note> notes = {
      note(0, 60, 0, 50),                            // released before the pedal: unchanged
      note(0, 61, 150, 200),                         // released under it: to the lift at 500
      note(1, 61, 150, 200),                         // another channel: unchanged
      note(0, 62, 150, 200), note(0, 62, 300, 350),  // struck again at 300: the first stops there, the second to 500
      note(0, 63, 550, 560),                         // released while up: unchanged
      note(0, 64, 610, 650),                         // pedal 64 counts as down; CC121 at 700 lifts it
      note(0, 65, 810, 900),                         // never lifted: to the song's end
      note(0, 66, 450, 500),                         // released at the lift's tick: the pedal is up then
  };
  const std::vector<std::uint64_t> expected = {50, 500, 200, 300, 500, 560, 700, 1000, 500};
  EXPECT_EQ(haptics::pedal_end_ticks(song, notes), expected);
}

TEST(SustainPedal, OffByDefaultAndOnWithTheOption) {
  midi::Song song;
  song.tempo_map = midi::TempoMap::metrical(500, {});  // 1 ms a tick at 120 bpm
  song.tracks.resize(1);
  song.controls = {cc(0, 0, 64, 127), cc(800, 0, 64, 0)};
  midi::Note n = note(0, 60, 100, 200);
  song.notes.push_back(n);
  song.tracks[0].note_count = 1;
  song.tracks[0].keys.add(60);
  song.end_tick = 1000;
  haptics::HapticOptions opts;
  EXPECT_NEAR(haptics::build_haptic_track(song, 0, opts).notes.at(0).end_s, 0.2, 1e-9);
  opts.pedal = true;
  const haptics::HapticTrack held = haptics::build_haptic_track(song, 0, opts);
  EXPECT_NEAR(held.notes.at(0).end_s, 0.8, 1e-9);
  EXPECT_EQ(held.notes.at(0).note.duration_ticks, 700u);  // device ticks at 1 kHz
}

}  // namespace
