// Session and transport control through the device: hello (and a wrong version), seek, stop, pause,
// emergency stop, preset upload, wrong-direction reports.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/firmware/host_link.hpp"

namespace hmp::test {
namespace {

// A device playing a long note plus queued notes for later, with the output settled at full level.
struct Playing {
  sim::SimDevice dev{1000};
  HostLink host{dev};
  Playing() {
    host.hello();
    host.settings(exact_settings());
    host.play();
    dev.advance(2);
    const std::uint64_t t = dev.tick();
    host.notes({{t + 5, 5000, 100.0, 0.8}});
    host.notes({{t + 400, 500, 70.0, 0.5}});
    host.long_note({t + 600, 500, 90.0, 0.5});
    host.run(100);
    host.collect();
  }
  // Largest |output| over the next `ticks` ticks (host alive).
  float peak(std::size_t ticks) {
    float m = 0.0f;
    for (const float y : host.run(ticks)) m = std::max(m, std::abs(y));
    return m;
  }
};

TEST(FirmwareTransport, HelloWithAnotherProtocolVersionIsRefusedButAnswered) {
  sim::SimDevice dev;
  HostLink host(dev);
  const std::uint16_t seq = host.hello(p::kProtocolVersion + 1);
  dev.advance(1);
  const Replies r = host.collect();
  ASSERT_EQ(r.hellos.size(), 1u);  // so the host learns which version the device speaks
  EXPECT_EQ(r.hellos[0].protocol_version, p::kProtocolVersion);
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_EQ(r.errors[0].code, p::ErrorCode::version_mismatch);
  EXPECT_EQ(r.errors[0].seq, seq);
  EXPECT_EQ(r.errors[0].type, static_cast<std::uint8_t>(p::Type::hello));
  const p::Status s = host.status();
  EXPECT_EQ(s.rejected, 1u);
  EXPECT_EQ(s.last_seq, seq);  // processed (and refused)
}

// After a Hello of another version the device understands only Hello, Sync and Estop until a Hello of
// its own version arrives (docs/protocol.md, versioning).
TEST(FirmwareTransport, AfterAWrongVersionOnlyHelloSyncAndEstopAreUnderstood) {
  sim::SimDevice dev;
  HostLink host(dev);
  host.hello(p::kProtocolVersion + 1);
  const std::uint16_t play = host.play();
  const std::uint16_t notes = host.notes({{dev.tick() + 10, 100, 100.0, 0.5}});
  host.sync(42);
  dev.advance(2);
  Replies r = host.collect();
  ASSERT_EQ(r.errors.size(), 3u);
  EXPECT_EQ(r.errors[1].seq, play);
  EXPECT_EQ(r.errors[1].code, p::ErrorCode::version_mismatch);
  EXPECT_EQ(r.errors[2].seq, notes);
  EXPECT_EQ(r.errors[2].code, p::ErrorCode::version_mismatch);
  ASSERT_EQ(r.syncs.size(), 1u);
  EXPECT_EQ(r.syncs[0].host_time_us, 42u);
  EXPECT_EQ(dev.core().queued_notes(), 0u);
  EXPECT_NE(host.status().state, p::State::playing);

  host.hello();
  host.play();
  dev.advance(2);
  r = host.collect();
  EXPECT_TRUE(r.errors.empty());
  EXPECT_EQ(host.status().state, p::State::playing);
}

TEST(FirmwareTransport, SeekCutsSoundingAndQueuedNotes) {
  Playing d;
  ASSERT_GT(d.peak(50), 0.5f);
  d.host.transport(p::TransportOp::seek, 123456);
  const std::vector<float> after = d.host.run(1500);
  for (std::size_t i = 0; i < after.size(); ++i) ASSERT_EQ(after[i], 0.0f) << "tick after seek " << i + 1;
  const Replies r = d.host.collect();
  EXPECT_EQ(r.started.size(), 0u);  // the queued notes never started
  const p::Status s = d.host.status();
  EXPECT_EQ(s.state, p::State::playing);
  EXPECT_EQ(s.queue_free, 256u / p::kNotesPerBatch);
  EXPECT_EQ(s.active_voices, 0u);
  // And playing goes on: a note sent after the seek sounds.
  const std::uint64_t t = d.dev.tick();
  d.host.notes({{t + 10, 200, 100.0, 0.5}});
  EXPECT_GT(d.peak(100), 0.4f);
}

TEST(FirmwareTransport, StopFadesOutWithinTwentyMillisecondsAndFlushes) {
  Playing d;
  d.host.transport(p::TransportOp::stop);
  const std::vector<float> after = d.host.run(1500);
  for (std::size_t i = 19; i < after.size(); ++i) ASSERT_EQ(after[i], 0.0f) << "tick after stop " << i + 1;
  // A fade, not a cut: the level falls over several ticks.
  EXPECT_GT(std::abs(after[2]) + std::abs(after[3]) + std::abs(after[4]), 0.0f);
  EXPECT_EQ(d.host.collect().started.size(), 0u);
  const p::Status s = d.host.status();
  EXPECT_EQ(s.state, p::State::stopped);
  EXPECT_EQ(s.queue_free, 256u / p::kNotesPerBatch);
}

TEST(FirmwareTransport, PauseSilencesAndPlayRampsBackIn) {
  Playing d;
  d.host.transport(p::TransportOp::pause);
  const std::vector<float> paused = d.host.run(300);
  for (std::size_t i = 19; i < paused.size(); ++i) ASSERT_EQ(paused[i], 0.0f);
  EXPECT_EQ(d.host.status().state, p::State::paused);
  // Play again with the default 500 ms ramp: a new note comes in gradually.
  p::Settings s = exact_settings();
  s.ramp_in_ms = 500;
  d.host.settings(s);
  d.host.play();
  const std::uint64_t t = d.dev.tick();
  d.host.notes({{t + 2, 2000, 100.0, 1.0}});
  const std::vector<float> ramp = d.host.run(1000);
  float early = 0.0f, late = 0.0f;
  for (std::size_t i = 0; i < 100; ++i) early = std::max(early, std::abs(ramp[i]));
  for (std::size_t i = 600; i < 1000; ++i) late = std::max(late, std::abs(ramp[i]));
  EXPECT_LE(early, 0.21f);  // ≤ 100/500 of full scale in the first 100 ms
  EXPECT_GT(late, 0.95f);
}

TEST(FirmwareTransport, EmergencyStopSilencesTheNextTickAndLatchesUntilStop) {
  Playing d;
  ASSERT_GT(d.peak(20), 0.5f);
  d.host.estop();
  const std::vector<float> after = d.host.run(200);
  for (std::size_t i = 0; i < after.size(); ++i) ASSERT_EQ(after[i], 0.0f) << "tick after estop " << i + 1;
  p::Status s = d.host.status();
  EXPECT_EQ(s.state, p::State::fault);
  EXPECT_NE(s.faults & p::fault_estop, 0u);
  // Play does not clear it: notes stay silent.
  d.host.play();
  const std::uint64_t t = d.dev.tick();
  d.host.notes({{t + 5, 300, 100.0, 1.0}});
  for (const float y : d.host.run(300)) ASSERT_EQ(y, 0.0f);
  EXPECT_NE(d.host.status().faults & p::fault_estop, 0u);
  // Stop acknowledges the fault; play then works again.
  d.host.transport(p::TransportOp::stop);
  d.host.run(5);
  s = d.host.status();
  EXPECT_EQ(s.faults, 0u);
  EXPECT_EQ(s.state, p::State::stopped);
  d.host.play();
  const std::uint64_t t2 = d.dev.tick();
  d.host.notes({{t2 + 5, 300, 100.0, 1.0}});
  EXPECT_GT(d.peak(300), 0.5f);
}

TEST(FirmwareTransport, EmergencyStopActsEvenBehindAFullInbox) {
  Playing d;
  // Fill the inbox with syncs without running the tick, then the estop: the inbox has no room for it.
  p::Message sync = p::make(p::Type::sync, 1);
  p::Report r;
  ASSERT_TRUE(p::encode(sync, r));
  while (d.dev.send_to_device(r)) {
  }
  p::Report estop;
  ASSERT_TRUE(p::encode(p::make(p::Type::estop, 2), estop));
  EXPECT_FALSE(d.dev.send_to_device(estop));
  d.dev.advance(1);
  EXPECT_EQ(d.dev.last_output(), 0.0f);
  EXPECT_NE(d.dev.core().faults() & p::fault_estop, 0u);
  EXPECT_NE(d.dev.core().faults() & p::fault_queue_overflow, 0u);  // the lost report is latched too
}

TEST(FirmwareTransport, HelloClearsALatchedFault) {
  Playing d;
  d.host.estop();
  d.host.run(5);
  d.host.hello();
  d.host.run(5);
  const p::Status s = d.host.status();
  EXPECT_EQ(s.faults, 0u);
  EXPECT_EQ(s.state, p::State::idle);
}

TEST(FirmwareTransport, NotesNeedAnUploadedPreset) {
  sim::SimDevice dev;
  HostLink host(dev);
  host.open_exact();
  dev.advance(2);
  const std::uint8_t slot = envelope::kFirstUserSlot + 3;
  const std::uint64_t t = dev.tick();
  TestNote n{t + 20, 300, 100.0, 0.7, slot};
  const std::uint16_t refused = host.notes({n});
  dev.advance(1);
  Replies r = host.collect();
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_EQ(r.errors[0].code, p::ErrorCode::bad_slot);
  EXPECT_EQ(r.errors[0].seq, refused);

  const envelope::Adsr adsr{30.0f, 40.0f, 80.0f, 0.5f, 0.1f, envelope::Shape::adsr};
  host.preset(slot, adsr);
  n.start = dev.tick() + 20;
  host.notes({n});
  const std::uint64_t first = dev.tick() + 1;
  const std::vector<float> got = host.run(400);
  // Reference: an engine with the same preset in the same slot.
  synth::Engine ref;
  ASSERT_TRUE(ref.set_preset(slot, adsr));
  for (std::size_t i = 0; i < got.size(); ++i) {
    if (first + i == n.start) ref.start(to_synth(n));
    ASSERT_EQ(got[i], ref.tick()) << "tick " << first + i;
  }
  EXPECT_EQ(host.status().rejected, 1u);
}

TEST(FirmwareTransport, UnplayableFrequenciesAreRefusedWholeBatch) {
  sim::SimDevice dev;
  HostLink host(dev);
  host.hello();
  host.play();
  dev.advance(2);
  const std::uint64_t t = dev.tick() + 50;
  // One good note and one at the Nyquist frequency (500 Hz at 1 kHz): the whole report is refused.
  host.notes({{t, 100, 100.0, 0.5}, {t, 100, 500.0, 0.5}});
  host.notes({{t, 100, 0.0, 0.5}});
  dev.advance(1);
  const Replies r = host.collect();
  ASSERT_EQ(r.errors.size(), 2u);
  EXPECT_EQ(r.errors[0].code, p::ErrorCode::bad_value);
  EXPECT_EQ(r.errors[1].code, p::ErrorCode::bad_value);
  EXPECT_EQ(dev.core().queued_notes(), 0u);
  host.run(200);
  EXPECT_EQ(host.collect().started.size(), 0u);
}

TEST(FirmwareTransport, DeviceReportTypesSentToTheDeviceAreRefused) {
  sim::SimDevice dev;
  HostLink host(dev);
  const std::uint16_t seq = host.send(p::make(p::Type::status, 0));
  dev.advance(1);
  const Replies r = host.collect();
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_EQ(r.errors[0].code, p::ErrorCode::wrong_direction);
  EXPECT_EQ(r.errors[0].seq, seq);
  EXPECT_EQ(r.errors[0].type, static_cast<std::uint8_t>(p::Type::status));
  EXPECT_EQ(dev.core().stats().rejected, 1u);
}

}  // namespace
}  // namespace hmp::test
