// Off-screen frames (the video export's) are the window's frames: the same FrameState drawn by the window
// on a private Xvfb display and by EGL without any display gives the same pixels. And the off-screen
// frames need no display at all.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <thread>

#include "host/view/roll_layout.hpp"
#include "host/view/view_backend.hpp"
#include "tests/support/xvfb.hpp"

namespace {

using namespace hmp::view;

hmp::midi::Song song_of_three_tracks() {
  hmp::midi::Song song;
  song.tempo_map = hmp::midi::TempoMap::metrical(500, {});
  song.tracks.resize(3);
  for (int i = 0; i < 60; ++i) {
    for (std::uint32_t t = 0; t < 3; ++t) {
      hmp::midi::Note n;
      n.track = t;
      n.start_tick = 300u * static_cast<std::uint64_t>(i) + 100u * t;
      n.end_tick = n.start_tick + 250 + 50 * t;
      n.key = static_cast<std::uint8_t>(48 + (i * 5 + static_cast<int>(t) * 7) % 30);
      n.velocity = 80;
      song.notes.push_back(n);
      song.tracks[t].note_count++;
      song.tracks[t].keys.add(n.key);
    }
  }
  return song;
}

FrameState state_at(std::int64_t song_us) {
  FrameState f;
  f.song_us = song_us;
  f.end_us = 18'000'000;
  f.haptic_track = 1;
  f.previous_haptic = 1;
  f.overlay = "offscreen test  0:05.0 / 0:18.0";
  f.legend = {
      {0, "0 one (Piano)", false, false}, {1, "1 two (Flute)", true, false}, {2, "2 three (Cello)", false, true}};
  f.vibration_samples = 200;
  for (int i = 0; i < 200; ++i) f.vibration[i] = 0.8f * std::sin(static_cast<float>(i) * 0.3f);
  return f;
}

TEST(Offscreen, DrawsWithoutADisplay) {
  const hmp::midi::Song song = song_of_three_tracks();
  unsetenv("DISPLAY");
  unsetenv("WAYLAND_DISPLAY");
  ViewSetup setup;
  setup.song = &song;
  setup.width = 320;
  setup.height = 180;
  std::string error;
  auto frames = open_offscreen(setup, error);
  ASSERT_TRUE(frames) << error;
  const std::uint8_t* px = frames->draw(state_at(5'000'000));
  ASSERT_NE(px, nullptr);
  // Something was drawn: more than one colour in the frame.
  std::size_t different = 0;
  for (std::size_t i = 4; i < 320u * 180u * 4u; i += 4)
    different += px[i] != px[0] || px[i + 1] != px[1] || px[i + 2] != px[2];
  EXPECT_GT(different, 1000u);
}

TEST(Offscreen, RejectsSizesOutOfRange) {
  const hmp::midi::Song song = song_of_three_tracks();
  ViewSetup setup;
  setup.song = &song;
  setup.width = 8;
  std::string error;
  EXPECT_FALSE(open_offscreen(setup, error));
  EXPECT_NE(error.find("out of"), std::string::npos) << error;
}

TEST(Offscreen, FramesEqualTheWindowsFrames) {
  ASSERT_TRUE(hmp::test::xvfb().running()) << "Xvfb did not start (package xvfb)";
  const hmp::midi::Song song = song_of_three_tracks();
  ViewSetup setup;
  setup.song = &song;
  setup.hidden = true;
  setup.capture = true;
  setup.vsync = false;
  std::string error;
  auto window = open_view(setup, error);
  ASSERT_TRUE(window) << error;
  int w = 0, h = 0;
  float scale = 0;
  window->size(w, h, scale);
  ASSERT_EQ(scale, 1.0f) << "Xvfb is not HiDPI";
  setup.width = w;
  setup.height = h;
  for (const std::int64_t t : {0LL, 2'345'678LL, 9'000'000LL, 17'999'000LL}) {
    const FrameState f = state_at(t);
    std::vector<ViewEvent> events;
    ASSERT_TRUE(window->frame(f, events));
    std::vector<std::uint8_t> shot;
    int sw = 0, sh = 0;
    ASSERT_TRUE(window->read_pixels(shot, sw, sh));
    ASSERT_EQ(sw, w);
    ASSERT_EQ(sh, h);
    // On a thread of its own: a thread holds one current context, and the window's (GLX) is current here.
    std::vector<std::uint8_t> frame;
    std::thread([&] {
      auto frames = open_offscreen(setup, error);
      if (!frames) return;
      const std::uint8_t* drawn = frames->draw(f);
      frame.assign(drawn, drawn + static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
    }).join();
    ASSERT_FALSE(frame.empty()) << error;
    const std::uint8_t* px = frame.data();
    std::size_t differ = 0;
    for (int y = 0; y < h; ++y) {  // the window's shot is top-down RGB, the off-screen frame bottom-up RGBA
      for (int x = 0; x < w; ++x) {
        const std::uint8_t* a =
            &shot[(static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)) * 3];
        const std::uint8_t* b =
            px + (static_cast<std::size_t>(h - 1 - y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)) * 4;
        differ += a[0] != b[0] || a[1] != b[1] || a[2] != b[2];
      }
    }
    EXPECT_EQ(differ, 0u) << "pixels differing at t = " << t << " µs";
  }
}

}  // namespace

namespace {

// `hmp live`'s notes, which are not the song's: drawn where the roll layout puts them (left of the
// present line, over the keys of the setup's range) in their channel's colour, and nowhere without them.
TEST(Offscreen, PlayedNotesAreDrawnWhereTheLayoutPutsThem) {
  hmp::midi::Song channels;
  channels.tracks.resize(16);
  ViewSetup setup;
  setup.song = &channels;
  setup.width = 640;
  setup.height = 360;
  setup.keys = std::pair{21, 108};
  std::string error;
  auto frames = open_offscreen(setup, error);
  ASSERT_TRUE(frames) << error;
  FrameState f;
  f.song_us = 5'000'000;
  f.haptic_track = 2;
  f.previous_haptic = 2;
  const Bar played{3'000'000, 4'500'000, 60, 100, 2};
  const std::size_t size = 640u * 360u * 4u;
  const std::uint8_t* px = frames->draw(f);
  const std::vector<std::uint8_t> without(px, px + size);
  f.played = {played};
  px = frames->draw(f);
  const std::vector<std::uint8_t> with(px, px + size);

  LayoutParams p = for_drawable(LayoutParams{}, 640, 360, 1.0f, f.seconds_across);
  p.key_low = 21;
  p.key_high = 108;
  const RollLayout layout(p, 16, 2);
  const Rect r = layout.bar_rect(played, f.song_us);
  ASSERT_LT(r.x1, roll_width(p) * 0.5f) << "a note that ended is in the past, left of the present";
  const Rgb c = layout.colour(played, f.song_us);
  const auto at = [&](const std::vector<std::uint8_t>& v, float x, float y) {  // bottom-up RGBA
    const std::size_t i =
        (static_cast<std::size_t>(359 - static_cast<int>(y)) * 640u + static_cast<std::size_t>(x)) * 4;
    return std::array<int, 3>{v[i], v[i + 1], v[i + 2]};
  };
  const float cx = (r.x0 + r.x1) / 2, cy = (r.y0 + r.y1) / 2;
  const std::array<int, 3> want = {static_cast<int>(std::lround(c.r * 255)), static_cast<int>(std::lround(c.g * 255)),
                                   static_cast<int>(std::lround(c.b * 255))};
  const std::array<int, 3> got = at(with, cx, cy);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[static_cast<std::size_t>(k)], want[static_cast<std::size_t>(k)], 2) << k;
  EXPECT_NE(at(without, cx, cy), got) << "the bar is the played note's, not the background";
  // Nothing else changed outside the bar (and its antialiased edge).
  std::size_t outside = 0;
  for (float y = 0; y < 360; ++y) {
    for (float x = 0; x < 640; ++x) {
      if (x >= r.x0 - 2 && x <= r.x1 + 2 && y >= r.y0 - 2 && y <= r.y1 + 2) continue;
      outside += at(with, x, y) != at(without, x, y);
    }
  }
  EXPECT_EQ(outside, 0u);
}

}  // namespace
