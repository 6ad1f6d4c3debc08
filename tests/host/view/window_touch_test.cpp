// Touching notes through the window (paper §5.3): `hmp play`'s window (cli/play_view) on the real-time
// simulated device, under a private Xvfb. A scripted cursor put on a flute bar ahead of the present makes
// the device start that very note within 20 ms of the cursor's arrival (its Started report); a cursor
// that follows a violin bar with the button held for more than 0.5 s makes the violin the haptic track.
// A pointer resting on the window (no button) plays nothing. The bars' places come from the window's own
// layout at the time of each event.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <optional>
#include <thread>

#include "host/cli/play_view.hpp"
#include "host/transport/sim_transport.hpp"
#include "tests/e2e/play_harness.hpp"
#include "tests/support/xvfb.hpp"

namespace {

using namespace std::chrono_literals;
namespace test = hmp::test;
using hmp::view::Clock;

constexpr std::uint32_t kFlute = 1, kViolin = 2;

std::optional<hmp::view::Bar> bar_of(std::uint32_t track, double from_s, double to_s) {
  const hmp::midi::Song& song = test::demo_song();
  for (const hmp::midi::Note& n : song.notes) {
    const double s = song.start_s(n);
    if (n.track == track && s >= from_s && s < to_s) {
      return hmp::view::Bar{song.start_us(n), song.end_us(n), n.key, n.velocity, n.track};
    }
  }
  return std::nullopt;
}

// Where the middle of `b` is in the window at song time `t_us`.
std::pair<float, float> centre_of(const hmp::view::LiveView& view, const hmp::view::Bar& b, std::int64_t t_us) {
  const hmp::view::Rect r = view.layout_at().bar_rect(b, t_us);
  return {(r.x0 + r.x1) / 2, (r.y0 + r.y1) / 2};
}

TEST(ViewTouch, TheCursorOnABarStartsThatNoteAndHoldingSwitchesTheTrack) {
  ASSERT_TRUE(hmp::test::xvfb().running()) << "Xvfb did not start (package xvfb)";
  hmp::transport::SimTransport sim;  // real time, as `--device sim`
  test::Session s(sim, test::passage(kFlute, 130, 150));
  hmp::haptics::HapticOptions haptic;
  std::string error;
  const std::unique_ptr<hmp::view::LiveView> view =
      hmp::cli::open_play_view(test::demo_song(), s.player(), s.audio(), haptic, {"touch test", "sim", false}, error);
  ASSERT_NE(view, nullptr) << error;
  s.start();
  const auto deadline = Clock::now() + 5s;
  while (s.player().snapshot().counters.notes_played < 3 && Clock::now() < deadline) std::this_thread::sleep_for(5ms);
  ASSERT_GE(s.player().snapshot().counters.notes_played, 3u);

  // A flute bar 1.5–3 s ahead (not sent yet: the lookahead is 0.2 s), in the window's right half.
  const double now_s = static_cast<double>(s.audio().song_time_us()) / 1e6;
  const auto flute = bar_of(kFlute, now_s + 1.5, now_s + 3.0);
  ASSERT_TRUE(flute.has_value());
  auto started = [&](const hmp::view::Bar& b) {
    for (const hmp::player::StartedNote& st : s.started()) {
      if (st.origin.track == b.track && st.origin.key == b.key && std::llround(st.origin.start_s * 1e6) == b.start_us) {
        return true;
      }
    }
    return false;
  };
  ASSERT_FALSE(started(*flute));
  const auto [fx, fy] = centre_of(*view, *flute, s.audio().song_time_us());
  const auto t0 = Clock::now();
  view->inject({hmp::view::ViewEvent::Kind::press, 0, fx, fy});  // the button down on it: a touch
  while (!started(*flute) && Clock::now() - t0 < 1s) std::this_thread::sleep_for(200us);
  ASSERT_TRUE(started(*flute)) << "the touched note never started";
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  RecordProperty("touch_ms", std::to_string(ms));
  std::printf("cursor on the bar → Started: %.1f ms\n", ms);
  EXPECT_LE(ms, 20.0);
  view->inject({hmp::view::ViewEvent::Kind::release, 0, fx, fy});

  // A pointer resting on the window touches nothing: bars passing under it for 0.5 s start no note of
  // their own (the player's own notes of the flute go on).
  const std::size_t before = s.started().size();
  view->inject({hmp::view::ViewEvent::Kind::cursor, 0, 640.0f, 360.0f});
  std::this_thread::sleep_for(500ms);
  const std::vector<hmp::player::StartedNote> after = s.started();
  for (std::size_t i = before; i < after.size(); ++i)
    EXPECT_EQ(after[i].origin.track, kFlute) << "a resting pointer played a note";

  // Follow a violin bar (the cursor moves with it as it scrolls), button held: after 0.5 s the violin
  // is the haptic track.
  const double later_s = static_cast<double>(s.audio().song_time_us()) / 1e6;
  const auto violin = bar_of(kViolin, later_s + 1.0, later_s + 5.0);
  ASSERT_TRUE(violin.has_value()) << "no violin note ahead";
  auto follow = [&] { return centre_of(*view, *violin, s.audio().song_time_us()); };
  const auto [vx, vy] = follow();
  view->inject({hmp::view::ViewEvent::Kind::cursor, 0, vx, vy});
  view->inject({hmp::view::ViewEvent::Kind::press, 0, vx, vy});
  const auto pressed = Clock::now();
  while (s.player().snapshot().track != kViolin && Clock::now() - pressed < 2s) {
    const auto [cx, cy] = follow();
    view->inject({hmp::view::ViewEvent::Kind::cursor, 0, cx, cy});
    std::this_thread::sleep_for(10ms);
  }
  const double held_s = std::chrono::duration<double>(Clock::now() - pressed).count();
  EXPECT_EQ(s.player().snapshot().track, kViolin);
  EXPECT_GE(held_s, 0.5) << "switched before the push lasted 0.5 s";
  view->inject({hmp::view::ViewEvent::Kind::release, 0, vx, vy});
  s.player().post(hmp::player::Command::quit);
  s.join();
}

}  // namespace
