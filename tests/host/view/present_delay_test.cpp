// The live view's delay from a frame's start to its swap (host/view/present_delay.hpp): one slow frame
// among steady ones does not move it, and a lasting change is followed within half its window; checked
// against the median of the same delays worked out here by sorting.
#include "host/view/present_delay.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace {

using hmp::view::PresentDelay;
using ms = std::chrono::milliseconds;

TEST(PresentDelay, OneSlowFrameDoesNotMoveIt) {
  PresentDelay d;
  d.add(ms(80));  // the first frame: shaders compiled
  EXPECT_EQ(d.get(), ms(8)) << "the guess stands against one frame";
  for (int i = 0; i < 8; ++i) d.add(ms(2));
  EXPECT_EQ(d.get(), ms(2));
  d.add(ms(500));  // a stall
  EXPECT_EQ(d.get(), ms(2));
}

TEST(PresentDelay, ALastingChangeIsFollowedWithinHalfTheWindow) {
  PresentDelay d;
  for (int i = 0; i < 8; ++i) d.add(ms(2));
  for (int i = 0; i < 3; ++i) d.add(ms(16));
  EXPECT_EQ(d.get(), ms(2));
  d.add(ms(16));
  EXPECT_EQ(d.get(), ms(16)) << "half the window slow: the upper median follows";
}

TEST(PresentDelay, IsTheUpperMedianOfTheLastEightDelays) {
  PresentDelay d;
  std::vector<ms> all(8, ms(8));
  unsigned x = 12345;
  for (int i = 0; i < 200; ++i) {
    x = x * 1103515245u + 12345u;
    const ms delay((x >> 16) % 40);
    d.add(delay);
    all.push_back(delay);
    std::vector<ms> last(all.end() - 8, all.end());
    std::sort(last.begin(), last.end());
    ASSERT_EQ(d.get(), last[4]) << "after " << i + 1 << " delays";
  }
}

}  // namespace
