// Live reports through the device (protocol 3): a note-on sounds on the tick the report is taken in and is
// reported Started there, a note-off releases it, a bend retunes it with the phase going on; a report is
// taken whole or refused whole, and only while playing. Expected samples are a double-precision sine and
// a free-standing Envelope, not the device's engine.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/firmware/host_link.hpp"

namespace hmp::test {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;
constexpr auto kSquare = static_cast<std::uint8_t>(envelope::Preset::square);
constexpr auto kOrgan = static_cast<std::uint8_t>(envelope::Preset::organ);

p::LiveEvent on(std::uint8_t key, double hz, std::uint8_t preset = kSquare, double amp = 0.5) {
  return {p::LiveOp::on, key, preset, synth::freq_to_q20(hz), synth::amp_to_q16(amp)};
}
p::LiveEvent off(std::uint8_t key) { return {p::LiveOp::off, key, 0, 0, 0}; }
p::LiveEvent bend(std::uint8_t key, double hz) { return {p::LiveOp::bend, key, 0, synth::freq_to_q20(hz), 0}; }

std::uint16_t live(HostLink& host, std::initializer_list<p::LiveEvent> events, std::uint8_t track = 0) {
  p::Message m = p::make(p::Type::live, 0);
  m.live.track = track;
  for (const p::LiveEvent& e : events) m.live.events[m.live.count++] = e;
  return host.send(m);
}

struct Rig {
  sim::SimDevice dev{1000};
  HostLink host{dev};
  Rig() {
    p::Settings s = exact_settings();
    s.end_fade_ms = 0;
    host.hello();
    host.settings(s);
    host.play();
    dev.advance(3);
    host.collect();
  }
};

TEST(Live, ANoteOnSoundsOnTheTickItIsTakenAndIsReportedStarted) {
  Rig r;
  const std::uint16_t seq = live(r.host, {on(60, 100), on(64, 125)});
  const std::uint64_t taken = r.dev.tick() + 1;  // the next tick takes the report from the inbox
  std::vector<float> out(200);
  r.dev.advance(1, out.data());
  const Replies replies = r.host.collect();  // sent in that tick: no waiting for the next Status
  r.dev.advance(out.size() - 1, out.data() + 1);
  ASSERT_EQ(replies.started.size(), 2u);
  for (std::uint8_t i = 0; i < 2; ++i) {
    EXPECT_EQ(replies.started[i].seq, seq);
    EXPECT_EQ(replies.started[i].index, i);
    EXPECT_EQ(replies.started[i].scheduled_tick, static_cast<std::uint32_t>(taken));
    EXPECT_EQ(replies.started[i].actual_tick, static_cast<std::uint32_t>(taken));
  }
  EXPECT_TRUE(replies.errors.empty());
  // Both notes from that very tick, phase 0 there, at the frequencies the wire carries.
  const double f1 = synth::q20_to_hz(synth::freq_to_q20(100)), f2 = synth::q20_to_hz(synth::freq_to_q20(125));
  const double amp = synth::amp_to_q16(0.5) / 65535.0;
  for (std::size_t k = 0; k < out.size(); ++k) {
    const double t = static_cast<double>(k) / 1000.0;
    const double want = amp * (std::sin(kTwoPi * f1 * t) + std::sin(kTwoPi * f2 * t));
    ASSERT_NEAR(out[k], want, 2e-4) << "tick " << k;
  }
  EXPECT_EQ(r.dev.core().engine().active_voices(), 2) << "held: no duration ends them";
}

TEST(Live, ANoteOffReleasesAndABendRetunes) {
  Rig r;
  live(r.host, {on(60, 80, kOrgan)});
  const std::uint64_t start = r.dev.tick() + 1;  // out[k]: the note's tick k
  std::vector<float> out(400);
  r.dev.advance(100, out.data());
  live(r.host, {bend(60, 90)});
  r.dev.advance(100, out.data() + 100);
  live(r.host, {off(61), off(60)});  // a key that is not sounding is ignored
  r.dev.advance(200, out.data() + 200);
  EXPECT_TRUE(r.host.collect().errors.empty());
  // The organ (5 ms attack, 25 ms release to 1 %): held through tick 199 (the release from the tick the
  // off is taken in), the frequency changing at tick 100 with the phase carried on.
  envelope::Envelope env;
  env.start_held(envelope::builtin(envelope::Preset::organ), synth::q16_to_amp(synth::amp_to_q16(0.5)), 1000, 0);
  const double f1 = synth::q20_to_hz(synth::freq_to_q20(80)), f2 = synth::q20_to_hz(synth::freq_to_q20(90));
  double phase = 0;
  for (std::uint32_t k = 0; k < 400; ++k) {
    if (k == 200) env.release_at(k);
    ASSERT_NEAR(out[k], static_cast<double>(env.at(k)) * std::sin(phase), 2e-4) << "tick " << k;
    phase += kTwoPi * (k < 100 ? f1 : f2) / 1000.0;
  }
  EXPECT_EQ(r.dev.core().engine().active_voices(), 0);
  EXPECT_EQ(start + 399, r.dev.tick());
}

TEST(Live, RefusedWholeWhenNotPlayingOrWhenAnEventCannotBePlayed) {
  sim::SimDevice dev(1000);
  HostLink host(dev);
  host.hello();
  dev.advance(2);
  host.collect();
  const std::uint16_t idle_seq = live(host, {on(60, 100)});
  dev.advance(2);
  Replies replies = host.collect();
  ASSERT_EQ(replies.errors.size(), 1u);
  EXPECT_EQ(replies.errors[0].code, p::ErrorCode::not_playing);
  EXPECT_EQ(replies.errors[0].seq, idle_seq);
  EXPECT_EQ(dev.core().engine().active_voices(), 0);

  host.play();
  dev.advance(2);
  host.collect();
  // A valid note-on with a bend past Nyquist, and one naming an empty preset slot: nothing starts.
  live(host, {on(60, 100), bend(60, 500)});
  live(host, {on(61, 100), on(62, 100, envelope::kFirstUserSlot)});
  dev.advance(2);
  replies = host.collect();
  ASSERT_EQ(replies.errors.size(), 2u);
  EXPECT_EQ(replies.errors[0].code, p::ErrorCode::bad_value);
  EXPECT_EQ(replies.errors[1].code, p::ErrorCode::bad_slot);
  EXPECT_TRUE(replies.started.empty());
  EXPECT_EQ(dev.core().engine().active_voices(), 0);
}

// Live reports use no queue slot: a session's credit for scheduled notes is untouched by them.
TEST(Live, UsesNoNoteCredit) {
  Rig r;
  const p::Status before = r.host.status();
  for (std::uint8_t k = 0; k < 40; ++k) {
    live(r.host, {on(k, 50 + k), off(k)});
    r.dev.advance(1);
  }
  const p::Status after = r.host.status();
  EXPECT_EQ(after.queue_free, before.queue_free);
  EXPECT_EQ(after.started - before.started, 40u);
  EXPECT_EQ(after.rejected, before.rejected);
}

}  // namespace
}  // namespace hmp::test
