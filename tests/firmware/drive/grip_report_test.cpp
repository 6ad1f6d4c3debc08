// Status reports where the grip is (protocol version 2, bytes 45–57): what the view's cursor follows when
// a hand moves the grip. The reference is the plant's own grip position (its integrated state, double
// precision), not the firmware's estimate: the report must follow a hand that moves the grip by
// centimetres. A device without a drive knows nothing and says so.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/firmware/drive/drive_rig.hpp"

namespace hmp::test {
namespace {

double distance_to_plant(const protocol::Status& st, const sim::plant::Vec3d& p) {
  const double dx = static_cast<double>(st.grip_m[0]) - p.x, dy = static_cast<double>(st.grip_m[1]) - p.y,
               dz = static_cast<double>(st.grip_m[2]) - p.z;
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

TEST(GripReport, FollowsTheHandThatMovesTheGrip) {
  DriveRig rig(1000);
  const protocol::Settings s = exact_settings();
  rig.start(s);
  rig.run(300, s.peak_force_n, false);  // settle at the bias
  protocol::Status st = rig.dev.core().status();
  ASSERT_EQ(st.grip_known, 1);
  const sim::plant::Vec3d rest = rig.dev.plant()->position();
  EXPECT_LT(distance_to_plant(st, rest), 0.5e-3) << "at rest";

  // The hand moves the grip 3 cm right, 2 cm down, 1 cm forward over 0.5 s, then holds it there.
  const sim::plant::Vec3d anchor0 = rig.dev.plant()->dynamics().finger_anchor();
  const sim::plant::Vec3d move{0.03, -0.02, 0.01};
  double worst = 0;
  for (int ms = 1; ms <= 800; ++ms) {
    const double f = std::min(1.0, ms / 500.0);
    rig.dev.move_hand({anchor0.x + f * move.x, anchor0.y + f * move.y, anchor0.z + f * move.z});
    rig.run(1, s.peak_force_n, false);
    st = rig.dev.core().status();
    ASSERT_EQ(st.grip_known, 1) << "at " << ms << " ms";
    // The estimate is one tick behind a grip moving at up to 7.5 cm/s: 75 µm, plus the fit's own error.
    worst = std::max(worst, distance_to_plant(st, rig.dev.plant()->position()));
  }
  EXPECT_LT(worst, 1.0e-3);
  const sim::plant::Vec3d end = rig.dev.plant()->position();
  const double moved = std::sqrt((end.x - rest.x) * (end.x - rest.x) + (end.y - rest.y) * (end.y - rest.y) +
                                 (end.z - rest.z) * (end.z - rest.z));
  EXPECT_GT(moved, 0.02) << "the hand did not move the grip: the test would prove nothing";
  EXPECT_EQ(rig.dev.core().faults(), 0u);
}

TEST(GripReport, UnknownWithoutADrive) {
  sim::SimOptions options;
  options.tick_hz = 1000;  // no plant: the board has no motors, the core no drive
  sim::SimDevice dev(options);
  HostLink host(dev);
  host.hello();
  dev.advance(50);
  const protocol::Status st = dev.core().status();
  EXPECT_EQ(st.grip_known, 0);
  EXPECT_EQ(st.grip_m[0], 0.0f);
  EXPECT_EQ(st.grip_m[1], 0.0f);
  EXPECT_EQ(st.grip_m[2], 0.0f);
}

}  // namespace
}  // namespace hmp::test
