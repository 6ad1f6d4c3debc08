// Live MIDI input → Live events: the byte stream (running status, realtime and system bytes), note pairs,
// velocity, the sustain pedal, pitch bend, channels, and the key range option. Frequencies are checked
// against the mapping of design §5 for a track of every key in the range, computed here from its formula
// (paper mode: f = f_min + (f_max − f_min)·rank/(k_ε − 1) over equally spaced keys).
#include "host/live/live_mapper.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "host/common/error.hpp"
#include "shared/synth/frequency.hpp"

namespace hmp::live {
namespace {

using Bytes = std::vector<std::uint8_t>;

std::vector<ChannelMessage> parse(MidiStream& s, const Bytes& b) {
  std::vector<ChannelMessage> out;
  s.feed(b.data(), b.size(), [&](const ChannelMessage& m) { out.push_back(m); });
  return out;
}

TEST(MidiStream, RunningStatusRealtimeAndSystemMessages) {
  MidiStream s;
  // Note-on, two more under running status, a clock byte inside the third, then a sysex (skipped, and it
  // ends the running status), data bytes after it (dropped), a program change (one data byte).
  const Bytes b = {0x90, 60, 100, 62, 90, 64, 0xF8, 80, 0xF0, 0x7E, 0x01, 0xF7, 1, 2, 0xC3, 5, 0xFE, 0xB0, 64, 127};
  const auto m = parse(s, b);
  ASSERT_EQ(m.size(), 5u);
  EXPECT_EQ(m[0].status, 0x90);
  EXPECT_EQ(m[1].data1, 62);
  EXPECT_EQ(m[2].data1, 64);
  EXPECT_EQ(m[2].data2, 80) << "a realtime byte inside a message does not end it";
  EXPECT_EQ(m[3].status, 0xC3);
  EXPECT_EQ(m[3].data1, 5);
  EXPECT_EQ(m[4].kind(), 0xB0);
  EXPECT_EQ(m[4].data2, 127);
}

TEST(MidiStream, AMessageCutAcrossFeeds) {
  MidiStream s;
  EXPECT_TRUE(parse(s, {0xE5, 0x00}).empty());
  const auto m = parse(s, {0x40, 0x10});  // completes the bend; 0x10 starts the next one (running status)
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].channel(), 5);
  EXPECT_EQ(m[0].data2, 0x40);
  const auto n = parse(s, {0x20});
  ASSERT_EQ(n.size(), 1u);
  EXPECT_EQ(n[0].data1, 0x10);
}

struct Rig {
  LiveMapper mapper;
  MidiStream stream;
  explicit Rig(MapperOptions o = {}) : mapper(o) {}
  std::vector<DeviceEvent> send(const Bytes& b) {
    std::vector<DeviceEvent> out;
    stream.feed(b.data(), b.size(), [&](const ChannelMessage& m) { mapper.on_message(m, out); });
    return out;
  }
};

// design §5, paper mode, a track of every key low…high: frequency linear in the key's rank.
double paper_hz(int key, const KeyRange& r, const mapping::Ranges& g = {}) {
  const int k = std::min(std::max(key, r.low), r.high);
  return g.f_min_hz + (g.f_max_hz - g.f_min_hz) * (k - r.low) / (r.high - r.low);
}

TEST(LiveMapper, NotePairsWithVelocityAndTheKeyRangesMapping) {
  Rig rig;
  const auto on = rig.send({0x90, 60, 127, 0x90, 72, 64});
  ASSERT_EQ(on.size(), 2u);
  EXPECT_EQ(on[0].event.op, protocol::LiveOp::on);
  EXPECT_EQ(on[0].event.key, 60);
  EXPECT_EQ(on[0].track, 0);
  EXPECT_NEAR(synth::q20_to_hz(on[0].event.freq_q20), paper_hz(60, KeyRange{}), 1e-5);
  EXPECT_NEAR(synth::q20_to_hz(on[1].event.freq_q20), paper_hz(72, KeyRange{}), 1e-5);
  // Half the velocity, half the mapped amplitude (of its own key).
  LiveMapper reference{MapperOptions{}};
  std::vector<DeviceEvent> full;
  reference.on_message({0x90, 72, 127}, full);
  EXPECT_NEAR(on[1].event.amp_q16, full[0].event.amp_q16 * 64.0 / 127.0, 1.0);
  const auto off = rig.send({0x80, 60, 0, 0x90, 72, 0});  // note-off, and note-on at velocity 0
  ASSERT_EQ(off.size(), 2u);
  EXPECT_EQ(off[0].event.op, protocol::LiveOp::off);
  EXPECT_EQ(off[1].event.key, 72);
  EXPECT_TRUE(rig.send({0x80, 60, 0}).empty()) << "a second note-off";
  EXPECT_EQ(rig.mapper.counts().notes_on, 2u);
  EXPECT_EQ(rig.mapper.counts().notes_off, 2u);
}

TEST(LiveMapper, KeysOutsideTheRangeMapAsItsEnds) {
  MapperOptions o;
  o.keys = {48, 72};
  Rig rig(o);
  const auto e = rig.send({0x90, 30, 100, 0x90, 100, 100});
  EXPECT_NEAR(synth::q20_to_hz(e[0].event.freq_q20), 50.0, 1e-5);
  EXPECT_NEAR(synth::q20_to_hz(e[1].event.freq_q20), 250.0, 1e-5);
}

TEST(LiveMapper, TheSustainPedalHoldsReleasedNotesUntilItLifts) {
  Rig rig;
  rig.send({0xB0, 64, 127, 0x90, 60, 100, 0x90, 64, 100});
  EXPECT_TRUE(rig.send({0x80, 60, 0}).empty()) << "kept by the pedal";
  // 60 struck again under the pedal: a new note (the device releases the former one itself).
  const auto again = rig.send({0x90, 60, 90});
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0].event.op, protocol::LiveOp::on);
  // The pedal lifts while 60 is held and 64 is not: only 64 ends.
  const auto lift = rig.send({0x80, 64, 0, 0xB0, 64, 0});
  ASSERT_EQ(lift.size(), 1u);
  EXPECT_EQ(lift[0].event.op, protocol::LiveOp::off);
  EXPECT_EQ(lift[0].event.key, 64);
  ASSERT_EQ(rig.send({0x80, 60, 0}).size(), 1u);
}

TEST(LiveMapper, PitchBendMovesEverySoundingNoteOfItsChannel) {
  Rig rig;
  rig.send({0x90, 60, 100, 0x91, 60, 100, 0x90, 62, 100});
  const auto up = rig.send({0xE0, 0x7F, 0x7F});  // full up: +2 semitones (less 1/8192)
  ASSERT_EQ(up.size(), 2u) << "channel 1's note is not bent";
  const double full = 2.0 * 8191 / 8192;
  EXPECT_NEAR(
      synth::q20_to_hz(up[0].event.freq_q20),
      std::exp(std::log(paper_hz(61, {})) + (full - 1) * (std::log(paper_hz(62, {})) - std::log(paper_hz(61, {})))),
      1e-5);
  EXPECT_EQ(up[0].event.op, protocol::LiveOp::bend);
  EXPECT_EQ(up[1].event.key, 62);
  // A note struck while bent starts bent; centring the bend (CC121) moves none, the next bend does.
  const auto bent_on = rig.send({0x90, 65, 100});
  EXPECT_NEAR(synth::q20_to_hz(bent_on[0].event.freq_q20), rig.mapper.frequency_hz(65 + full), 1e-5);
  EXPECT_TRUE(rig.send({0xB0, 121, 0}).empty());
  const auto centre = rig.send({0xE0, 0x00, 0x40});
  ASSERT_EQ(centre.size(), 3u);
  EXPECT_NEAR(synth::q20_to_hz(centre[2].event.freq_q20), paper_hz(65, {}), 1e-5);
}

TEST(LiveMapper, OneChannelChosenAndAllNotesOff) {
  MapperOptions o;
  o.channel = 9;
  Rig rig(o);
  EXPECT_TRUE(rig.send({0x90, 60, 100, 0x95, 61, 100}).empty());
  EXPECT_EQ(rig.mapper.counts().other_channels, 2u);
  ASSERT_EQ(rig.send({0x99, 36, 100, 0x99, 38, 100}).size(), 2u);
  const auto off = rig.send({0xB9, 123, 0});
  ASSERT_EQ(off.size(), 2u);
  EXPECT_EQ(off[0].track, 9);
  EXPECT_TRUE(rig.send({0x89, 36, 0}).empty());
  // Aftertouch, program change, channel pressure: nothing.
  EXPECT_TRUE(rig.send({0xA9, 36, 5, 0xC9, 3, 0xD9, 9}).empty());
}

TEST(LiveMapper, KeyRangeOption) {
  EXPECT_EQ(parse_key_range("21:108").low, 21);
  EXPECT_EQ(parse_key_range("A0:C8").high, 108);
  EXPECT_EQ(parse_key_range("c#4:Db5").low, 61);
  EXPECT_EQ(parse_key_range("c#4:Db5").high, 73);
  EXPECT_EQ(parse_key_range("C-1:G9").high, 127);
  EXPECT_EQ(to_string(KeyRange{}), "21:108 (A0–C8)");
  for (const char* bad : {"60", "x:y", "70:60", "0:128", ":", "C4:", "H2:C4", "C4:C10", "-1:5"})
    EXPECT_THROW(parse_key_range(bad), BadInput) << bad;
  try {
    parse_key_range("70:60");
  } catch (const BadInput& e) {
    EXPECT_EQ(std::string(e.what()), "--key-range '70:60': the low key is above the high one");
  }
}

}  // namespace
}  // namespace hmp::live
