// A sixteen-track song as the window draws it (the view module's off-screen frames: the window's painter
// through EGL, no display needed), read back pixel by pixel against the layout's rectangles: the felt
// track's blue appears on its own bars only, the fifteen other tracks show fifteen different colours, no
// bar reaches under the legend's panel (a long note is cut at the roll's edge, the panel beside it
// untouched), where a felt bar and another overlap the felt one is on top, and no layer is shifted out
// of the roll into the overlay line above it. HMP_VIEW_16_SHOT=FILE.ppm
// also writes the frame (the picture in docs/view.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "host/view/roll_layout.hpp"
#include "host/view/view_backend.hpp"
#include "tests/host/view/millisecond_song.hpp"

namespace {

using namespace hmp::view;

constexpr int kWidth = 1280, kHeight = 720;
constexpr std::uint32_t kTracks = 16, kFelt = 5;
constexpr std::int64_t kNow = 20'000'000;

// Sixteen tracks on a 1 ms tick, each with its own band of keys (overlapping its neighbours') and its
// own rhythm; tracks 4 and 6 also double the felt track's notes a little earlier and later, so bars of
// different layers cross; track 3 holds one long note past the roll's right edge.
hmp::midi::Song sixteen_tracks() {
  hmp::midi::Song song = hmp::view::test::millisecond_song(kTracks);
  auto add = [&](std::uint32_t track, std::uint64_t start_ms, std::uint64_t ms, int key) {
    hmp::view::test::add_note(song, track, start_ms, ms, key);
  };
  for (std::uint32_t t = 0; t < kTracks; ++t) {
    const std::uint64_t period = 450 + 37 * t;
    for (std::uint64_t start = 100 * t; start < 40'000; start += period) {
      const int key = 36 + static_cast<int>(3 * t) + static_cast<int>((start / period) % 5);
      add(t, start, period * 2 / 3, key);
      if (t == kFelt) {
        add(kFelt - 1, start - 150, 300, key);
        add(kFelt + 1, start + 150, 300, key);
      }
    }
  }
  add(3, 21'000, 30'000, 30);
  return song;
}

struct Frame {
  std::vector<std::uint8_t> rgba;  // rows bottom up, as OpenGL gives them
  Rgb at(float x, float y) const {
    const auto row = static_cast<std::size_t>(kHeight - 1 - static_cast<int>(y));
    const std::size_t i = (row * kWidth + static_cast<std::size_t>(x)) * 4;
    return {rgba[i] / 255.0f, rgba[i + 1] / 255.0f, rgba[i + 2] / 255.0f};
  }
};

bool near(const Rgb& a, const Rgb& b, float tolerance = 0.02f) {
  return std::fabs(a.r - b.r) < tolerance && std::fabs(a.g - b.g) < tolerance && std::fabs(a.b - b.b) < tolerance;
}

class SixteenTracks : public ::testing::Test {
 protected:
  void SetUp() override {
    song_ = sixteen_tracks();
    ViewSetup setup;
    setup.song = &song_;
    setup.width = kWidth;
    setup.height = kHeight;
    std::string error;
    frames_ = open_offscreen(setup, error);
    ASSERT_TRUE(frames_) << error;
    FrameState state;
    state.song_us = kNow;
    state.end_us = 40'000'000;
    state.haptic_track = kFelt;
    state.previous_haptic = kFelt;
    state.seconds_across = 12.0;
    state.overlay = "sixteen tracks  0:20.0 / 0:40.0";
    for (std::uint32_t t = 0; t < kTracks; ++t)
      state.legend.push_back({t, std::to_string(t) + " track", t == kFelt, false});
    const std::uint8_t* px = frames_->draw(state);
    ASSERT_NE(px, nullptr);
    frame_.rgba.assign(px, px + static_cast<std::size_t>(kWidth) * kHeight * 4);
    if (const char* out = std::getenv("HMP_VIEW_16_SHOT")) {
      if (std::FILE* f = std::fopen(out, "wb")) {
        std::fprintf(f, "P6 %d %d 255\n", kWidth, kHeight);
        for (int y = 0; y < kHeight; ++y)
          for (int x = 0; x < kWidth; ++x) {
            const Rgb c = frame_.at(static_cast<float>(x), static_cast<float>(y));
            const unsigned char p[3] = {static_cast<unsigned char>(std::lround(c.r * 255)),
                                        static_cast<unsigned char>(std::lround(c.g * 255)),
                                        static_cast<unsigned char>(std::lround(c.b * 255))};
            std::fwrite(p, 1, 3, f);
          }
        std::fclose(f);
      }
    }
    LayoutParams p = for_drawable(LayoutParams{}, kWidth, kHeight, 1.0f, 12.0);
    const auto [lo, hi] = key_range(song_);
    p.key_low = lo;
    p.key_high = hi;
    layout_.emplace(p, kTracks, kFelt);
    for (const hmp::midi::Note& n : song_.notes) {
      const Bar b{song_.start_us(n), song_.end_us(n), n.key, n.velocity, n.track};
      if (b.end_us < layout_->window_begin_us(kNow) || b.start_us > layout_->window_end_us(kNow)) continue;
      bars_.push_back(b);
    }
  }

  // Whether (x, y) is inside a bar of `track` (with `slack` px around it).
  bool inside(std::uint32_t track, float x, float y, float slack) const {
    for (const Bar& b : bars_) {
      if (b.track != track) continue;
      const Rect r = layout_->bar_rect(b, kNow);
      if (x > r.x0 - slack && x < r.x1 + slack && y > r.y0 - slack && y < r.y1 + slack) return true;
    }
    return false;
  }
  // Whether a bar of a layer in front of `track` covers (x, y) (with a pixel of slack).
  bool covered_from_front(std::uint32_t track, float x, float y) const {
    for (std::uint32_t t = 0; t < kTracks; ++t) {
      if (layout_->depth_of(t) < layout_->depth_of(track) && inside(t, x, y, 1.5f)) return true;
    }
    return false;
  }

  hmp::midi::Song song_;
  std::unique_ptr<OffscreenFrames> frames_;
  Frame frame_;
  std::optional<RollLayout> layout_;
  std::vector<Bar> bars_;
};

TEST_F(SixteenTracks, TheFeltBlueIsOnItsOwnBarsOnly) {
  const float roll = roll_width(layout_->params());
  const float top = layout_->params().margin_px, bottom = static_cast<float>(kHeight) - layout_->params().margin_px;
  int blue = 0;
  for (float y = top - 20; y < bottom; y += 1) {
    for (float x = 0; x < roll; x += 1) {
      if (!near(frame_.at(x, y), kHapticBlue, 0.06f)) continue;
      ++blue;
      EXPECT_TRUE(inside(kFelt, x, y, 1.5f)) << "felt blue at (" << x << ", " << y << ")";
    }
  }
  EXPECT_GT(blue, 2000);
}

TEST_F(SixteenTracks, EveryOtherTrackShowsAColourOfItsOwn) {
  std::vector<std::pair<std::uint32_t, Rgb>> shown;
  for (std::uint32_t t = 0; t < kTracks; ++t) {
    if (t == kFelt) continue;
    for (const Bar& b : bars_) {
      if (b.track != t || NoteIndex::sounding(b, kNow)) continue;
      const Rect r = layout_->bar_rect(b, kNow);
      const float x = (r.x0 + r.x1) / 2, y = (r.y0 + r.y1) / 2;
      if (r.x1 - r.x0 < 6 || x < 2 || x > roll_width(layout_->params()) - 2 || covered_from_front(t, x, y)) continue;
      // Another bar of the same layer or one behind may still be drawn later: take pixels that match
      // in a 3 × 1 run, the bar's own fill.
      const Rgb c = frame_.at(x, y);
      if (!near(frame_.at(x - 2, y), c, 0.005f) || !near(frame_.at(x + 2, y), c, 0.005f)) continue;
      shown.push_back({t, c});
      break;
    }
  }
  ASSERT_EQ(shown.size(), kTracks - 1) << "a track with no bar in view, uncovered";
  for (std::size_t i = 0; i < shown.size(); ++i) {
    EXPECT_FALSE(near(shown[i].second, kHapticBlue, 0.1f)) << "track " << shown[i].first;
    for (std::size_t j = i + 1; j < shown.size(); ++j) {
      EXPECT_FALSE(near(shown[i].second, shown[j].second, 0.05f))
          << "tracks " << shown[i].first << " and " << shown[j].first;
    }
  }
}

TEST_F(SixteenTracks, NoBarReachesUnderTheLegend) {
  const Chrome chrome = chrome_layout(layout_->params());
  for (const Bar& b : bars_) EXPECT_LE(layout_->bar_rect(b, kNow).x1, chrome.legend.x0) << "track " << b.track;
  // Track 3's long note runs to the roll's edge and stops there; the panel's first columns, left of the
  // swatches, are the panel's colour from top to bottom.
  const Rect long_note = layout_->bar_rect(Bar{21'000'000, 51'000'000, 30, 90, 3}, kNow);
  const float y = (long_note.y0 + long_note.y1) / 2;
  EXPECT_FALSE(near(frame_.at(chrome.legend.x0 - 2, y), kBackground)) << "the long note is drawn up to the edge";
  for (float yy = chrome.legend.y0 + 1; yy < chrome.legend.y1 - 1; yy += 1) {
    EXPECT_TRUE(near(frame_.at(chrome.legend.x0 + 2, yy), kPanel)) << "at y " << yy;
  }
}

TEST_F(SixteenTracks, TheFeltBarIsOnTopWhereBarsOverlap) {
  int overlaps = 0;
  for (const Bar& felt : bars_) {
    if (felt.track != kFelt) continue;
    const Rect f = layout_->bar_rect(felt, kNow);
    for (const Bar& other : bars_) {
      if (other.track == kFelt) continue;
      const Rect o = layout_->bar_rect(other, kNow);
      const float x0 = std::max(f.x0, o.x0) + 1, x1 = std::min(f.x1, o.x1) - 1;
      const float y0 = std::max(f.y0, o.y0) + 1, y1 = std::min(f.y1, o.y1) - 1;
      if (x1 <= x0 || y1 <= y0 || x0 < 0 || x1 > roll_width(layout_->params())) continue;
      const Rgb c = frame_.at((x0 + x1) / 2, (y0 + y1) / 2);
      EXPECT_TRUE(near(c, kHapticBlue) || near(c, kSoundingYellow)) << "over track " << other.track;
      ++overlaps;
    }
  }
  EXPECT_GE(overlaps, 8);
}

TEST_F(SixteenTracks, TheDeepestLayerStaysNearTheRoll) {
  // Fifteen layers behind share the 30 px of depth (2 px each, not 6), so the top row's bars of the
  // deepest layer rise at most 30 px above the roll's top.
  float highest = 1e9f;
  for (const Bar& b : bars_) highest = std::min(highest, layout_->bar_rect(b, kNow).y0);
  EXPECT_GE(highest, layout_->params().margin_px - 30.0f - 1e-3f);
  const Bar probe{kNow + 1'000'000, kNow + 2'000'000, 60, 90, 0};
  const Bar front{kNow + 1'000'000, kNow + 2'000'000, 60, 90, kFelt};
  EXPECT_NEAR(layout_->bar_rect(probe, kNow).x0 - layout_->bar_rect(front, kNow).x0,
              2.0f * static_cast<float>(layout_->depth_of(0)), 1e-3f);
}

}  // namespace
