// VirtualCard (host/audio/virtual_card.hpp), the simulated sound card the audio–haptic skew is
// measured with: the frames it asks for are contiguous and heard one buffer after they were asked for,
// at its crystal's rate; a callback that takes longer than the buffer is an underrun that delays
// everything after it by the time the card ran dry.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "host/audio/virtual_card.hpp"
#include "tests/support/load_guard.hpp"

namespace {

using hmp::audio::VirtualCard;
using namespace std::chrono_literals;

double ms_between(VirtualCard::TimePoint a, VirtualCard::TimePoint b) {
  return std::chrono::duration<double, std::milli>(a - b).count();
}

TEST(VirtualCard, FramesAreHeardOneBufferAfterTheyAreAskedForAtTheCrystalsRate) {
  VirtualCard::Settings s;
  s.ppm = 500;  // exaggerated, to see it
  s.record_frames = 4800;
  std::atomic<int> calls{0};
  std::atomic<float> next{0};
  const hmp::test::LoadWatch load;
  VirtualCard card(s, [&](float* left, float* right, int frames) {
    for (int i = 0; i < frames; ++i) left[i] = right[i] = next = next + 1e-6f;  // a ramp: shows order
    ++calls;
  });
  std::this_thread::sleep_for(120ms);
  card.stop();
  // The card's thread must run every 5 ms: a machine that does not give it that is not this card's fault.
  HMP_SKIP_IF_TOO_LOADED(load, card.underruns() == 0 && calls.load() >= 15,
                         card.underruns() << " underrun(s), " << calls.load() << " periods in 120 ms");
  // The buffer: 4 periods of 256 frames at 48 kHz × (1 + 500 ppm).
  const double rate = 48000 * (1 + 500e-6);
  EXPECT_NEAR(card.latency_s(), 1024 / rate, 1e-12);
  EXPECT_NEAR(ms_between(card.heard_at(48000), card.heard_at(0)), 48000 / rate * 1e3, 1e-6);
  EXPECT_GE(calls.load(), 15);  // ~22 periods in 120 ms
  EXPECT_EQ(card.frames_played(), static_cast<std::uint64_t>(calls.load()) * 256u);
  const std::vector<float> rec = card.recording();
  ASSERT_EQ(rec.size(), std::min<std::size_t>(4800, card.frames_played()));
  for (std::size_t i = 1; i < rec.size(); ++i) ASSERT_GT(rec[i], rec[i - 1]) << i;  // contiguous, in order
  EXPECT_EQ(card.underruns(), 0u);
}

TEST(VirtualCard, ACallbackSlowerThanTheBufferIsAnUnderrunThatDelaysWhatFollows) {
  VirtualCard::Settings s;
  std::atomic<int> calls{0};
  VirtualCard card(s, [&](float*, float*, int) {
    if (++calls == 10) std::this_thread::sleep_for(60ms);  // the buffer holds 21 ms
  });
  std::this_thread::sleep_for(150ms);
  card.stop();
  ASSERT_GE(card.underruns(), 1u);
  // Period 9 (frame 2304) was needed ~21 ms after it was asked for and came ~60 ms after: everything
  // from it on is heard ≥ 35 ms later than the nominal line; what came before is not.
  const double nominal_gap = 256.0 / 48000 * 1e3;
  EXPECT_NEAR(ms_between(card.heard_at(2048), card.heard_at(1792)), nominal_gap, 1e-6);
  EXPECT_GT(ms_between(card.heard_at(2304), card.heard_at(2048)) - nominal_gap, 35.0);
  // The first underrun is described as it happened: period 9's stream time, ~60 − 21 ms short, a
  // callback of ≥ 60 ms: the cause, not the wake-up before it.
  const std::vector<VirtualCard::Underrun> list = card.underrun_list();
  ASSERT_EQ(list.size(), card.underruns());
  EXPECT_DOUBLE_EQ(list[0].at_s, 2304 / 48000.0);
  EXPECT_GE(list[0].callback_ms, 60.0);
  EXPECT_GE(list[0].short_ms, 60.0 - 1024 / 48.0 - 1.0);
  EXPECT_LT(list[0].woke_late_ms, list[0].callback_ms);
}

}  // namespace
