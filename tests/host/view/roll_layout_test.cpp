// Where the animation puts each bar and in which colour (host/view/roll_layout.hpp), against the picture's
// rules computed here independently: x from the time (present at the centre line, the future right), y
// from the key (high keys up), each layer behind the haptic track shifted up and right; the haptic track
// blue, yellow while it sounds; other sounding notes white; the front-most bar wins a pick; switching the
// haptic track brings it to the front.
#include <gtest/gtest.h>

#include <cmath>

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
  return p;
}

TEST(ViewRollLayout, BarsSitWhereTimeKeyAndDepthPutThem) {
  const RollLayout layout(params(), 3, 1);  // track 1 is the haptic one
  const std::int64_t now = 42'000'000;
  const double px_per_s = 1280.0 / 10.0, row = (720.0 - 80.0) / 40.0;
  const std::uint32_t expected_depth[3] = {1, 0, 2};
  for (std::uint32_t track = 0; track < 3; ++track) {
    EXPECT_EQ(layout.depth_of(track), expected_depth[track]);
    const Bar b{now + 1'500'000, now + 2'000'000, 60, 90, track};
    const Rect r = layout.bar_rect(b, now);
    const double shift = 6.0 * expected_depth[track];
    EXPECT_NEAR(r.x0, 640.0 + 1.5 * px_per_s + shift, 1e-3);
    EXPECT_NEAR(r.x1, 640.0 + 2.0 * px_per_s + shift, 1e-3);
    EXPECT_NEAR(r.y0, 40.0 + (79 - 60) * row - shift, 1e-3);
    EXPECT_GT(r.y1, r.y0);
    EXPECT_LE(double{r.y1}, double{r.y0} + row);
  }
  // The present is the centre line; the past leaves on the left; higher keys are higher up.
  EXPECT_FLOAT_EQ(layout.x_of(now, now), 640.0f);
  EXPECT_FLOAT_EQ(layout.x_of(now - 5'000'000, now), 0.0f);
  EXPECT_LT(layout.y_of(79), layout.y_of(40));
  // The window covers the screen, and on the left a bit more for the shifted layers.
  EXPECT_EQ(layout.window_end_us(now), now + 5'000'000);
  EXPECT_LT(layout.window_begin_us(now), now - 5'000'000);
}

TEST(ViewRollLayout, ColoursFollowTheRules) {
  const RollLayout layout(params(), 8, 2);
  const std::int64_t now = 10'000'000;
  const Bar haptic_later{now + 100, now + 200, 60, 90, 2}, haptic_now{now - 100, now + 100, 62, 90, 2};
  EXPECT_EQ(layout.colour(haptic_later, now), kHapticBlue);
  EXPECT_EQ(layout.colour(haptic_now, now), kSoundingYellow);
  const Bar other_now{now - 100, now + 100, 50, 90, 0}, other_later{now + 100, now + 200, 50, 90, 0};
  EXPECT_EQ(layout.colour(other_now, now), kSoundingWhite);
  // The other tracks never look like the haptic one, whatever their number.
  for (std::uint32_t t = 0; t < 8; ++t) {
    if (t == 2) continue;
    const Rgb c = layout.colour(Bar{now + 100, now + 200, 50, 90, t}, now);
    EXPECT_NE(c, kHapticBlue);
    EXPECT_NE(c, kSoundingYellow);
    EXPECT_NE(c, kSoundingWhite);
  }
  // Seek and pause: a bar lit at one time is not at another (sounding is a function of the time).
  EXPECT_EQ(layout.colour(haptic_now, now + 1'000'000), kHapticBlue);
  EXPECT_NE(layout.colour(other_later, now), kSoundingWhite);
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
}

}  // namespace
