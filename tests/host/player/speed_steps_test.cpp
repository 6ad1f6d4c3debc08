// The [ and ] keys' speed steps (player::next_speed), shared by hmp play and hmp view: each step is the
// next of 0.5, 0.75, 1, 1.25, 1.5, 2 in its direction, clamped at the ends; a speed between steps (from
// --speed) steps from 1.
#include <gtest/gtest.h>

#include <vector>

#include "host/player/player.hpp"

namespace {

using hmp::player::next_speed;

TEST(SpeedSteps, WalkUpAndDownTheListAndStopAtTheEnds) {
  const std::vector<double> steps = {0.5, 0.75, 1.0, 1.25, 1.5, 2.0};
  for (std::size_t i = 0; i < steps.size(); ++i) {
    EXPECT_EQ(next_speed(steps[i], +1), steps[std::min(i + 1, steps.size() - 1)]) << steps[i];
    EXPECT_EQ(next_speed(steps[i], -1), steps[i == 0 ? 0 : i - 1]) << steps[i];
  }
  EXPECT_EQ(next_speed(hmp::player::kMaxSpeed, +1), 2.0);
  EXPECT_EQ(next_speed(hmp::player::kMinSpeed, -1), 0.5);
}

TEST(SpeedSteps, ASpeedBetweenStepsStepsFromOne) {
  EXPECT_EQ(next_speed(1.1, +1), 1.25);
  EXPECT_EQ(next_speed(1.1, -1), 0.75);
  EXPECT_EQ(next_speed(0.0, +1), 1.25);
}

}  // namespace
