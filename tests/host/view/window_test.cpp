// The animation window itself (the view module: SDL2 + OpenGL 3.3 core, Mesa's llvmpipe on a private
// Xvfb display): screenshots of real frames at known song times against the picture computed here from
// the notes — the haptic track's bars blue where their time and key put them, a note sounding then
// yellow, the other track in its own colour behind, nothing drawn where no note is; after a switch of the
// haptic track the new one is in front. Without a display: one line saying so, no window.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <optional>

#include "host/view/roll_layout.hpp"
#include "host/view/view_backend.hpp"
#include "tests/host/view/millisecond_song.hpp"
#include "tests/support/xvfb.hpp"

namespace {

using namespace hmp::view;

// Two tracks on a 1 ms tick (500 ticks per quarter at 120 bpm): track 0's notes on keys 60–67, track 1's
// on 55–62, overlapping in time and key so the layers cover each other.
hmp::midi::Song two_tracks() {
  hmp::midi::Song song = hmp::view::test::millisecond_song(2);
  auto add = [&](std::uint32_t track, std::uint64_t start_ms, std::uint64_t ms, int key) {
    hmp::view::test::add_note(song, track, start_ms, ms, key);
  };
  for (int i = 0; i < 40; ++i) {
    add(0, 1000u + 500u * i, 400, 60 + i % 8);
    add(1, 1200u + 700u * i, 900, 55 + i % 8);
  }
  return song;
}

struct Shot {
  std::vector<std::uint8_t> rgb;
  int w = 0, h = 0;
  Rgb at(float x, float y) const {
    const auto i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)) * 3;
    return {rgb[i] / 255.0f, rgb[i + 1] / 255.0f, rgb[i + 2] / 255.0f};
  }
};

bool near(const Rgb& a, const Rgb& b) {
  return std::abs(a.r - b.r) < 0.02f && std::abs(a.g - b.g) < 0.02f && std::abs(a.b - b.b) < 0.02f;
}

Shot shoot(ViewWindow& w, std::int64_t song_us, std::uint32_t haptic) {
  FrameState state;
  state.song_us = song_us;
  state.haptic_track = haptic;
  state.seconds_across = 12.0;
  std::vector<ViewEvent> events;
  Shot s;
  for (int i = 0; i < 2; ++i) EXPECT_TRUE(w.frame(state, events));  // the second frame on a mapped window
  EXPECT_TRUE(w.read_pixels(s.rgb, s.w, s.h));
  return s;
}

TEST(ViewWindow, WithoutADisplayItSaysSoInOneLine) {
  const char* saved = std::getenv("DISPLAY");
  const std::string keep = saved != nullptr ? saved : "";
  ::unsetenv("DISPLAY");
  ::unsetenv("WAYLAND_DISPLAY");
  const hmp::midi::Song song = two_tracks();
  ViewSetup setup;
  setup.song = &song;
  std::string error;
  EXPECT_EQ(open_view(setup, error), nullptr);
  EXPECT_NE(error.find("no display"), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos);
  if (!keep.empty()) ::setenv("DISPLAY", keep.c_str(), 1);
}

TEST(ViewWindow, FramesShowTheNotesWhereTheyBelong) {
  ASSERT_TRUE(hmp::test::xvfb().running()) << "Xvfb did not start (package xvfb)";
  const hmp::midi::Song song = two_tracks();
  ViewSetup setup;
  setup.song = &song;
  setup.capture = true;
  setup.vsync = false;
  std::string error;
  const std::unique_ptr<ViewWindow> w = open_view(setup, error);
  ASSERT_NE(w, nullptr) << error;
  RecordProperty("renderer", w->renderer());

  const std::int64_t now = 6'100'000;  // track 0's note at 6.0–6.4 s sounds; track 1's notes overlap it
  const Shot s = shoot(*w, now, 0);
  if (const char* out = std::getenv("HMP_VIEW_SHOT")) {  // a picture for the docs (binary PPM)
    std::FILE* f = std::fopen(out, "wb");
    if (f != nullptr) {
      std::fprintf(f, "P6 %d %d 255\n", s.w, s.h);
      std::fwrite(s.rgb.data(), 1, s.rgb.size(), f);
      std::fclose(f);
    }
  }
  ASSERT_EQ(s.w, 1280);
  ASSERT_EQ(s.h, 720);

  // The picture computed from the notes: the roll is the window less the legend's 240 px panel on the
  // right; x from time (12 s across the roll, the present at its centre), y from the key (the song's keys
  // 55–67 with the view's margin: key_range), layer 1 shifted 6 px up and right.
  const double roll = 1280.0 - 240.0;
  const std::pair<int, int> keys = key_range(song);
  const int key_low = keys.first, key_high = keys.second;  // a lambda below uses them
  const double row = (720.0 - 2 * 40.0) / (key_high - key_low + 1);
  auto centre = [&](std::int64_t start_us, std::int64_t end_us, int key, int depth) {
    const double x0 = roll / 2 + static_cast<double>(start_us - now) / 12e6 * roll + 6.0 * depth;
    const double x1 = roll / 2 + static_cast<double>(end_us - now) / 12e6 * roll + 6.0 * depth;
    const double y0 = 40.0 + (key_high - key) * row - 6.0 * depth;
    return std::pair{static_cast<float>((x0 + x1) / 2), static_cast<float>(y0 + row / 2)};
  };
  int blue = 0, yellow = 0;
  for (const hmp::midi::Note& n : song.notes) {
    if (n.track != 0) continue;
    const std::int64_t s_us = song.start_us(n), e_us = song.end_us(n);
    const auto [cx, cy] = centre(s_us, e_us, n.key, 0);
    if (cx < 5 || static_cast<double>(cx) > roll - 5) continue;  // off the roll
    const bool sounding = s_us <= now && now < e_us;
    const Rgb got = s.at(cx, cy);
    EXPECT_TRUE(near(got, sounding ? kSoundingYellow : kHapticBlue))
        << "track 0 note at " << s_us << " µs key " << int(n.key) << ": (" << got.r << "," << got.g << "," << got.b
        << ")";
    (sounding ? yellow : blue)++;
  }
  EXPECT_GE(blue, 10);
  EXPECT_EQ(yellow, 1);

  // Nothing where no note is: every sampled point of the roll outside all bars (with a pixel of slack at
  // their edges, the centre line and the strip) is background.
  int empty = 0;
  const Rgb background{0.07f, 0.07f, 0.08f};
  for (double y = 50; y < 650; y += 7) {
    for (double xx = 3; xx < roll - 3; xx += 11) {
      if (std::abs(xx - roll / 2) < 3) continue;
      bool covered = false;
      for (const hmp::midi::Note& n : song.notes) {
        const int depth = n.track == 0 ? 0 : 1;
        const double x0 = roll / 2 + static_cast<double>(song.start_us(n) - now) / 12e6 * roll + 6.0 * depth;
        const double x1 = roll / 2 + static_cast<double>(song.end_us(n) - now) / 12e6 * roll + 6.0 * depth;
        const double y0 = 40.0 + (key_high - n.key) * row - 6.0 * depth;
        covered = covered || (xx > x0 - 2 && xx < x1 + 2 && y > y0 - 2 && y < y0 + row + 2);
      }
      if (covered) continue;
      EXPECT_TRUE(near(s.at(static_cast<float>(xx), static_cast<float>(y)), background))
          << "something drawn at (" << xx << ", " << y << ")";
      ++empty;
    }
  }
  EXPECT_GT(empty, 800);

  // Switching the haptic track: where a bar of each track overlap, the new haptic track is in front
  // (blue or yellow), the old one behind in a track colour.
  const Shot switched = shoot(*w, now, 1);
  int front = 0;
  for (const hmp::midi::Note& n : song.notes) {
    if (n.track != 1) continue;
    const auto [cx, cy] = centre(song.start_us(n), song.end_us(n), n.key, 0);
    if (cx < 5 || static_cast<double>(cx) > roll - 5) continue;
    const Rgb got = switched.at(cx, cy);
    EXPECT_TRUE(near(got, kHapticBlue) || near(got, kSoundingYellow)) << "track 1 at " << song.start_us(n);
    ++front;
  }
  EXPECT_GE(front, 8);
}

}  // namespace
