// Touching a note (paper §5.3, the view's touch): Player::touch plays that note on the device at once —
// its Started report arrives within 20 ms of the touch (the median of three), for notes of the haptic
// track and of another track — while the song plays on the real-time simulated device. A note that does not exist
// plays nothing. Selecting a track (the view's legend, pushing into a bar) makes it the haptic track. The notes are
// taken from the song as the MIDI reader reads it.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <thread>
#include <vector>

#include "host/midi/song.hpp"
#include "host/transport/sim_transport.hpp"
#include "play_harness.hpp"

namespace {

using namespace std::chrono_literals;
namespace test = hmp::test;
using Clock = std::chrono::steady_clock;

constexpr std::uint32_t kFlute = 1;

// The first `count` notes of `track` starting at or after `from_s` (and before to_s), from the song model.
std::vector<hmp::midi::Note> notes_of(std::uint32_t track, double from_s, double to_s, std::size_t count) {
  std::vector<hmp::midi::Note> found;
  for (const hmp::midi::Note& n : test::demo_song().notes) {
    const double s = test::demo_song().start_s(n);
    if (n.track == track && s >= from_s && s < to_s && found.size() < count) found.push_back(n);
  }
  return found;
}

// Touches a note and returns how long until the device reported starting it (nullopt: not within 1 s).
std::optional<double> touch_latency_ms(test::Session& s, const hmp::midi::Note& n) {
  const double start_s = test::demo_song().start_s(n);
  auto started_now = [&] {
    for (const hmp::player::StartedNote& st : s.started()) {
      if (st.origin.track == n.track && st.origin.key == n.key && std::fabs(st.origin.start_s - start_s) < 1e-6)
        return true;
    }
    return false;
  };
  EXPECT_FALSE(started_now()) << "the note was played before it was touched: the test would prove nothing";
  const auto t0 = Clock::now();
  s.player().touch(n.track, n.key, start_s);
  while (Clock::now() - t0 < 1s) {
    if (started_now()) return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    std::this_thread::sleep_for(200us);
  }
  return std::nullopt;
}

TEST(PlayTouch, TouchedNotesStartWithin20ms) {
  hmp::transport::SimTransport sim;  // real time, as `--device sim`
  test::Session s(sim, test::passage(kFlute, 130, 150));
  s.start();
  const auto deadline = Clock::now() + 5s;
  while (s.player().snapshot().counters.notes_played < 3 && Clock::now() < deadline) std::this_thread::sleep_for(5ms);
  ASSERT_GE(s.player().snapshot().counters.notes_played, 3u);

  // Flute notes far ahead (not sent yet: the lookahead is 0.2 s) and notes of another track, three of
  // each: the bound holds for their median, so that one wake-up the machine delays (a VM's stalls reach
  // 39 ms, docs/performance.md) does not decide it; none may take more than 100 ms.
  for (const std::uint32_t track : {kFlute, 2u}) {
    const std::vector<hmp::midi::Note> notes = notes_of(track, track == kFlute ? 146 : 140, 150, 3);
    ASSERT_EQ(notes.size(), 3u) << "track " << track;
    std::vector<double> latencies;
    for (const hmp::midi::Note& n : notes) {
      const std::optional<double> ms = touch_latency_ms(s, n);
      ASSERT_TRUE(ms.has_value()) << "track " << n.track << " key " << int(n.key) << " never started";
      EXPECT_LE(*ms, 100.0) << "track " << n.track << " key " << int(n.key);
      latencies.push_back(*ms);
    }
    std::sort(latencies.begin(), latencies.end());
    EXPECT_LE(latencies[1], 20.0) << "track " << track << ": median of " << latencies[0] << ", " << latencies[1] << ", "
                                  << latencies[2] << " ms";
    testing::Test::RecordProperty("touch_ms_track_" + std::to_string(track), std::to_string(latencies[1]));
  }

  // A note that is not in the song: nothing starts.
  const std::size_t before = s.started().size();
  s.player().touch(kFlute, 20, 131.0);  // key 20 is below the flute's range
  std::this_thread::sleep_for(50ms);
  for (std::size_t i = before; i < s.started().size(); ++i) EXPECT_NE(s.started()[i].origin.key, 20);

  // Selecting a track makes it the haptic track: the notes the device starts from then on are its notes.
  s.player().select_track(999);  // no such track: nothing changes
  std::this_thread::sleep_for(30ms);
  EXPECT_EQ(s.player().snapshot().track, kFlute);
  s.player().select_track(2);
  const auto t0 = Clock::now();
  while (s.player().snapshot().track != 2 && Clock::now() - t0 < 1s) std::this_thread::sleep_for(1ms);
  ASSERT_EQ(s.player().snapshot().track, 2u);
  const std::size_t at_switch = s.started().size();
  const auto t1 = Clock::now();
  while (s.started().size() < at_switch + 3 && Clock::now() - t1 < 3s) std::this_thread::sleep_for(5ms);
  const auto started = s.started();
  ASSERT_GE(started.size(), at_switch + 3);
  for (std::size_t i = at_switch; i < started.size(); ++i) EXPECT_EQ(started[i].origin.track, 2u);
  s.player().post(hmp::player::Command::quit);
  s.join();
}

}  // namespace
