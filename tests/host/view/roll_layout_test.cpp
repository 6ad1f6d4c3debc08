// Where the animation puts each bar and in which colour (host/view/roll_layout.hpp), against the picture's
// rules computed here independently: the roll is the window less the legend's panel; x from the time
// (present at the roll's centre line, the future right, cut at the roll's edge), y from the key (high
// keys up), each layer behind the haptic track shifted up and right and 0.6 of a row high; the haptic
// track blue, yellow while it sounds; the others their own colour, white while they sound, both at 0.7 of
// the way from the background; the front-most bar wins a pick; switching the haptic track brings it to
// the front.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "host/view/roll_layout.hpp"

namespace {

using namespace hmp::view;

LayoutParams params() {
  LayoutParams p;
  p.width_px = 1280;
  p.height_px = 720;
  p.seconds_across = 10.0;
  p.key_low = 40;
  p.key_high = 79;  // 40 rows
  p.margin_px = 40.0f;
  p.depth_step_px = 6.0f;
  p.legend_px = 280.0f;  // the roll: 1000 px
  return p;
}

Rgb behind(const Rgb& c) {
  const Rgb bg{0.07f, 0.07f, 0.08f};
  return {bg.r + 0.7f * (c.r - bg.r), bg.g + 0.7f * (c.g - bg.g), bg.b + 0.7f * (c.b - bg.b)};
}

TEST(ViewRollLayout, BarsSitWhereTimeKeyAndDepthPutThem) {
  const RollLayout layout(params(), 3, 1);  // track 1 is the haptic one
  const std::int64_t now = 42'000'000;
  const double px_per_s = 1000.0 / 10.0, row = (720.0 - 80.0) / 40.0;
  const std::uint32_t expected_depth[3] = {1, 0, 2};
  for (std::uint32_t track = 0; track < 3; ++track) {
    EXPECT_EQ(layout.depth_of(track), expected_depth[track]);
    const Bar b{now + 1'500'000, now + 2'000'000, 60, 90, track};
    const Rect r = layout.bar_rect(b, now);
    const double shift = 6.0 * expected_depth[track];
    const double height = (row - 1) * (expected_depth[track] == 0 ? 1.0 : 0.6);
    EXPECT_NEAR(r.x0, 500.0 + 1.5 * px_per_s + shift, 1e-3);
    EXPECT_NEAR(r.x1, 500.0 + 2.0 * px_per_s + shift, 1e-3);
    EXPECT_NEAR(r.y0, 40.0 + (79 - 60) * row - shift + (row - 1 - height) / 2, 1e-3);
    EXPECT_NEAR(r.y1 - r.y0, height, 1e-3);
  }
  // The present is the roll's centre line; the past leaves on the left; higher keys are higher up.
  EXPECT_FLOAT_EQ(layout.x_of(now, now), 500.0f);
  EXPECT_FLOAT_EQ(layout.x_of(now - 5'000'000, now), 0.0f);
  EXPECT_LT(layout.y_of(79), layout.y_of(40));
  // The window covers the roll, and on the left a bit more for the shifted layers.
  EXPECT_EQ(layout.window_end_us(now), now + 5'000'000);
  EXPECT_LT(layout.window_begin_us(now), now - 5'000'000);
  // The future ends at the roll's edge, before the legend: a bar running past it is cut there, one
  // starting past it is a sliver at the edge.
  const Rect long_bar = layout.bar_rect(Bar{now + 4'000'000, now + 9'000'000, 60, 90, 1}, now);
  EXPECT_FLOAT_EQ(long_bar.x1, 1000.0f);
  const Rect shifted = layout.bar_rect(Bar{now + 4'990'000, now + 6'000'000, 60, 90, 2}, now);
  EXPECT_LE(shifted.x1, 1000.0f);
  const Chrome chrome = chrome_layout(layout.params());
  EXPECT_FLOAT_EQ(chrome.legend.x0, 1000.0f);
  EXPECT_GE(chrome.legend_x0, chrome.legend.x0);
  EXPECT_LE(chrome.legend_x0 + chrome.legend_width, 1280.0f);
}

TEST(ViewRollLayout, ColoursFollowTheRules) {
  const RollLayout layout(params(), 16, 2);
  const std::int64_t now = 10'000'000;
  const Bar haptic_later{now + 100, now + 200, 60, 90, 2}, haptic_now{now - 100, now + 100, 62, 90, 2};
  EXPECT_EQ(layout.colour(haptic_later, now), kHapticBlue);
  EXPECT_EQ(layout.colour(haptic_now, now), kSoundingYellow);
  const Bar other_now{now - 100, now + 100, 50, 90, 0}, other_later{now + 100, now + 200, 50, 90, 0};
  EXPECT_EQ(layout.colour(other_now, now), behind(kSoundingWhite));
  EXPECT_EQ(layout.colour(other_later, now), behind(kTrackColours[0]));
  // Every other track has a colour of its own, none the haptic one's, whatever their number (16).
  std::vector<Rgb> seen{kHapticBlue, kSoundingYellow, behind(kSoundingWhite)};
  for (std::uint32_t t = 0; t < 16; ++t) {
    if (t == 2) continue;
    const Rgb c = layout.colour(Bar{now + 100, now + 200, 50, 90, t}, now);
    EXPECT_EQ(c, behind(kTrackColours[t])) << "track " << t;
    EXPECT_EQ(layout.track_colour(t), c);
    for (const Rgb& other : seen) EXPECT_NE(c, other) << "track " << t;
    seen.push_back(c);
  }
  // Seek and pause: a bar lit at one time is not at another (sounding is a function of the time).
  EXPECT_EQ(layout.colour(haptic_now, now + 1'000'000), kHapticBlue);
  // While the layers glide after a switch, the old haptic track brightens back to behind and the new one
  // comes to full strength, blue at once.
  RollLayout gliding(params(), 16, 0);
  gliding.set_depth_blend(2, 0.5f);
  const Rgb half = gliding.colour(Bar{now + 100, now + 200, 50, 90, 2}, now);
  EXPECT_NEAR(half.g, 0.07f + 0.85f * (kTrackColours[2].g - 0.07f), 1e-5f);
  EXPECT_EQ(gliding.colour(Bar{now + 100, now + 200, 50, 90, 0}, now), kHapticBlue);
}

TEST(ViewRollLayout, PickTakesTheFrontBarAndSwitchingBringsATrackForward) {
  const std::int64_t now = 0;
  const Bar back{-1'000'000, 1'000'000, 60, 90, 0}, front{-1'000'000, 1'000'000, 60, 90, 1};
  const std::vector<Bar> visible{back, front};
  {
    const RollLayout layout(params(), 2, 1);
    const Rect r = layout.bar_rect(front, now);
    const auto hit = layout.pick(visible, now, (r.x0 + r.x1) / 2, (r.y0 + r.y1) / 2);
    ASSERT_TRUE(hit.has_value());
    EXPECT_EQ(hit->track, 1u);
    EXPECT_FALSE(layout.pick(visible, now, 5.0f, 5.0f).has_value()) << "nothing in the corner";
  }
  {
    const RollLayout switched(params(), 2, 0);  // track 0 became the haptic track: it is in front now
    EXPECT_EQ(switched.depth_of(0), 0u);
    EXPECT_EQ(switched.depth_of(1), 1u);
    const Rect r = switched.bar_rect(back, now);
    const auto hit = switched.pick(visible, now, (r.x0 + r.x1) / 2, (r.y0 + r.y1) / 2);
    ASSERT_TRUE(hit.has_value());
    EXPECT_EQ(hit->track, 0u);
  }
}

TEST(ViewRollLayout, KeyRangeCoversTheSongWithRoom) {
  hmp::midi::Song song;
  song.tracks.resize(2);
  song.tracks[0].note_count = 3;
  song.tracks[0].keys.add(60);
  song.tracks[0].keys.add(64);
  song.tracks[1].note_count = 1;
  song.tracks[1].keys.add(58);
  const auto [lo, hi] = key_range(song);
  EXPECT_LE(lo, 56);
  EXPECT_GE(hi, 66);
  EXPECT_GE(hi - lo, 24);
  EXPECT_GE(lo, 0);
  EXPECT_LE(hi, 127);
  hmp::midi::Song none;
  const auto [a, b] = key_range(none);
  EXPECT_LT(a, b);
  // Keys the user chose stand as they are, narrower than two octaves and beyond the song's.
  EXPECT_EQ(key_range(song, std::pair{70, 75}), std::pair(70, 75));
}

}  // namespace
