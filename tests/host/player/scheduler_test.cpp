// The player's note batching (host/player/note_batcher.hpp) and scheduling (scheduler.hpp): every
// report decodes to exactly the notes that went in (checked through the protocol codec, with the
// device's rule for extending the 32-bit base tick written here again), batches obey the wire limits,
// and the scheduler hands out every note of the window once, in order, within the horizon.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "host/player/note_batcher.hpp"
#include "host/player/scheduler.hpp"

namespace {

using hmp::player::DeviceNote;
using hmp::player::make_report;
namespace protocol = hmp::protocol;

DeviceNote note(std::uint64_t tick, std::uint32_t duration = 100, std::uint8_t track = 1) {
  DeviceNote n;
  n.start_tick = tick;
  n.duration_ticks = duration;
  n.freq_q20 = static_cast<std::uint32_t>(tick * 7 + 1) << 8;
  n.amp_q16 = static_cast<std::uint16_t>(tick * 13 + 5);
  n.preset = static_cast<std::uint8_t>(tick % 11);
  n.track = track;
  return n;
}

// What a device whose clock reads `now` makes of a report (docs/protocol.md, Note encoding).
std::vector<DeviceNote> device_view(const protocol::Message& m, std::uint64_t now) {
  protocol::Report r;
  EXPECT_TRUE(protocol::encode(m, r));
  protocol::Message d;
  EXPECT_EQ(protocol::decode(r, d), protocol::ErrorCode::none);
  std::vector<DeviceNote> out;
  if (d.type == protocol::Type::long_note) {
    const auto& l = d.long_note;
    out.push_back({l.start_tick, l.duration_ticks, l.freq_q20, l.amp_q16, l.preset, l.track});
    return out;
  }
  const std::int64_t base =
      static_cast<std::int64_t>(now) + static_cast<std::int32_t>(d.notes.base_tick - static_cast<std::uint32_t>(now));
  for (std::uint8_t i = 0; i < d.notes.count; ++i) {
    const auto& c = d.notes.notes[i];
    out.push_back({static_cast<std::uint64_t>(base) + c.offset, c.duration_ticks, c.freq_q20, c.amp_q16, c.preset,
                   d.notes.track});
  }
  return out;
}

void expect_same(const DeviceNote& a, const DeviceNote& b) {
  EXPECT_EQ(a.start_tick, b.start_tick);
  EXPECT_EQ(a.duration_ticks, b.duration_ticks);
  EXPECT_EQ(a.freq_q20, b.freq_q20);
  EXPECT_EQ(a.amp_q16, b.amp_q16);
  EXPECT_EQ(a.preset, b.preset);
  EXPECT_EQ(a.track, b.track);
}

TEST(PlayerBatcher, FiveNotesWithin255TicksShareOneReport) {
  const std::vector<DeviceNote> notes = {note(1000), note(1000), note(1100), note(1200), note(1255), note(1256)};
  protocol::Message m;
  ASSERT_EQ(make_report(notes, m), 5u);
  EXPECT_EQ(m.type, protocol::Type::notes);
  const auto seen = device_view(m, 990);
  ASSERT_EQ(seen.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) expect_same(seen[i], notes[i]);
}

TEST(PlayerBatcher, StartsBeyondTheOffsetRangeTrackChangesAndLongNotesSplit) {
  protocol::Message m;
  const std::vector<DeviceNote> far = {note(1000), note(1256)};
  EXPECT_EQ(make_report(far, m), 1u);
  const std::vector<DeviceNote> tracks = {note(1000), note(1001, 100, 1), note(1002, 100, 2)};
  EXPECT_EQ(make_report(tracks, m), 2u);
  const std::vector<DeviceNote> then_long = {note(1000), note(1001, 0x1000000)};
  EXPECT_EQ(make_report(then_long, m), 1u);
  EXPECT_EQ(m.type, protocol::Type::notes);
  const std::vector<DeviceNote> edge = {note(1000, 0xFFFFFF)};  // the longest compact duration
  EXPECT_EQ(make_report(edge, m), 1u);
  EXPECT_EQ(m.type, protocol::Type::notes);
}

TEST(PlayerBatcher, LongNoteCarriesTheFull64BitStartAndDuration) {
  const std::vector<DeviceNote> notes = {note((std::uint64_t{1} << 36) + 17, 0xFFFFFFFFu),
                                         note((std::uint64_t{1} << 36) + 18)};
  protocol::Message m;
  ASSERT_EQ(make_report(notes, m), 1u);
  EXPECT_EQ(m.type, protocol::Type::long_note);
  const auto seen = device_view(m, 0);
  ASSERT_EQ(seen.size(), 1u);
  expect_same(seen[0], notes[0]);
}

TEST(PlayerBatcher, BaseTickSurvivesThe32BitWrap) {
  const std::uint64_t wrap = std::uint64_t{1} << 32;
  const std::vector<DeviceNote> notes = {note(wrap - 3), note(wrap - 1), note(wrap), note(wrap + 200)};
  protocol::Message m;
  ASSERT_EQ(make_report(notes, m), 4u);
  for (const std::uint64_t now : {wrap - 150, wrap + 50}) {  // the device reads its clock before or after the wrap
    const auto seen = device_view(m, now);
    ASSERT_EQ(seen.size(), 4u);
    for (std::size_t i = 0; i < 4; ++i) expect_same(seen[i], notes[i]);
  }
}

TEST(PlayerBatcher, RandomRunsDecodeToExactlyTheNotesInOrder) {
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<std::uint64_t> gap(0, 400);
  std::uniform_int_distribution<std::uint32_t> duration(1, 0x1FFFFFF);
  std::uniform_int_distribution<int> track(0, 1);
  for (int run = 0; run < 200; ++run) {
    std::vector<DeviceNote> notes;
    std::uint64_t t = rng() >> 24;
    for (int i = 0; i < 60; ++i) {
      t += gap(rng) < 100 ? 0 : gap(rng);
      notes.push_back(note(t, duration(rng), static_cast<std::uint8_t>(track(rng))));
    }
    std::vector<DeviceNote> decoded;
    std::span<const DeviceNote> rest(notes);
    while (!rest.empty()) {
      protocol::Message m;
      const std::size_t used = make_report(rest, m);
      ASSERT_GE(used, 1u);
      ASSERT_LE(used, protocol::kNotesPerBatch);
      for (const DeviceNote& d : device_view(m, rest.front().start_tick)) decoded.push_back(d);
      rest = rest.subspan(used);
    }
    ASSERT_EQ(decoded.size(), notes.size());
    for (std::size_t i = 0; i < notes.size(); ++i) expect_same(decoded[i], notes[i]);
  }
}

hmp::haptics::HapticTrack track_of(const std::vector<double>& starts) {
  hmp::haptics::HapticTrack t;
  t.track = 3;
  for (std::size_t i = 0; i < starts.size(); ++i) {
    hmp::haptics::HapticNote h;
    h.start_s = starts[i];
    h.end_s = starts[i] + 0.1;
    h.key = static_cast<std::uint8_t>(60 + i % 20);
    h.note = note(static_cast<std::uint64_t>(starts[i] * 1000), 100, 3);
    t.notes.push_back(h);
  }
  return t;
}

TEST(PlayerScheduler, HandsOutTheWindowOnceInOrderWithinTheHorizon) {
  std::vector<double> starts;
  for (int i = 0; i < 300; ++i) starts.push_back(i * 0.037);  // 0 … 11.06 s
  hmp::player::Scheduler s(2'000'000, 9'000'000);
  s.load(track_of(starts), 0);
  std::size_t expected = 0;
  for (const double t : starts) expected += (t >= 2.0 && t < 9.0) ? 1 : 0;
  EXPECT_EQ(s.size(), expected);
  // Device tick = song ms + 5000; the horizon walks in 50-tick steps.
  const auto tick_of = [](const hmp::player::NoteSound& n) {
    return static_cast<std::uint64_t>(n.start_us / 1000 + 5000);
  };
  std::vector<hmp::player::NoteOrigin> got;
  for (std::uint64_t horizon = 5000; !s.finished(); horizon += 50) {
    while (auto r = s.next(horizon, 0, tick_of)) {
      for (const auto& n : r->notes) {
        EXPECT_LE(n.tick, horizon);
        EXPECT_EQ(n.track, 3u);
        got.push_back(n);
      }
    }
  }
  ASSERT_EQ(got.size(), expected);
  std::size_t k = 0;
  for (const double t : starts) {
    if (!(t >= 2.0 && t < 9.0)) continue;
    EXPECT_DOUBLE_EQ(got[k].start_s, t);
    EXPECT_EQ(got[k].tick, static_cast<std::uint64_t>(std::llround(t * 1e6)) / 1000 + 5000);
    ++k;
  }
  EXPECT_EQ(s.skipped(), 0u);
}

// The passage ends at --to: a note still sounding there is cut there, its ticks in proportion (render and
// sim end it there too); a note starting at --to is not in the passage.
TEST(PlayerScheduler, ANoteSoundingAtTheEndOfThePassageStopsThere) {
  hmp::player::Scheduler s(0, 1'050'000);
  s.load(track_of({0.5, 1.0, 1.05}), 0);
  EXPECT_EQ(s.size(), 2u);
  EXPECT_EQ(s.last_end_us(), 1'050'000);
  const auto tick_of = [](const hmp::player::NoteSound& n) { return static_cast<std::uint64_t>(n.start_us / 1000); };
  std::vector<hmp::player::NoteOrigin> got;
  while (auto r = s.next(10'000, 0, tick_of))
    for (const auto& n : r->notes) got.push_back(n);
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].duration_ticks, 100u);  // 0.5–0.6 s: within the passage, whole
  EXPECT_EQ(got[1].duration_ticks, 50u);   // 1.0–1.1 s: cut at 1.05 s
}

TEST(PlayerScheduler, SeekStartsAtTheFirstNoteAtOrAfterThePosition) {
  hmp::player::Scheduler s(0, INT64_MAX);
  s.load(track_of({1.0, 2.0, 2.0, 3.0}), 0);
  const auto tick_of = [](const hmp::player::NoteSound& n) { return static_cast<std::uint64_t>(n.start_us / 1000); };
  s.seek(2'000'000);
  auto r = s.next(1'000'000, 0, tick_of);
  ASSERT_TRUE(r);
  ASSERT_EQ(r->notes.size(), 2u);  // 3.0 is 1000 ticks after 2.0: another batch
  EXPECT_DOUBLE_EQ(r->notes[0].start_s, 2.0);
  s.seek(2'000'001);
  r = s.next(1'000'000, 0, tick_of);
  ASSERT_TRUE(r);
  EXPECT_DOUBLE_EQ(r->notes[0].start_s, 3.0);
  s.seek(10'000'000);
  EXPECT_TRUE(s.finished());
}

TEST(PlayerScheduler, NotesThatEndedLongAgoAreSkippedAndCounted) {
  hmp::player::Scheduler s(0, INT64_MAX);
  s.load(track_of({1.0, 1.5, 5.0}), 0);
  const auto tick_of = [](const hmp::player::NoteSound& n) { return static_cast<std::uint64_t>(n.start_us / 1000); };
  // Stale before tick 1601: notes ending at 1100 and 1600 are skipped, the one at 5000 is sent.
  auto r = s.next(10'000, 1601, tick_of);
  ASSERT_TRUE(r);
  EXPECT_DOUBLE_EQ(r->notes.at(0).start_s, 5.0);
  EXPECT_EQ(s.skipped(), 2u);
  // Ending exactly at the stale tick is not stale.
  hmp::player::Scheduler t(0, INT64_MAX);
  t.load(track_of({1.5}), 0);
  EXPECT_TRUE(t.next(10'000, 1600, tick_of));
}

}  // namespace
