// Pose from string lengths (shared/spidar/pose): lengths come from the independent double reference of
// spidar_reference.hpp, exact or quantised like the encoder; errors are measured against the true pose.
#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>

#include "shared/spidar/geometry.hpp"
#include "shared/spidar/pose.hpp"
#include "tests/shared/spidar/spidar_reference.hpp"

namespace {

using namespace hmp::spidar;
using spidar_ref::M3;
using spidar_ref::V3;

// Encoder: 512 lines × 4 on a 5 mm pulley (design §11).
constexpr double kQuantum = 2 * spidar_ref::kPi * 0.005 / 2048;

void record(const char* key, double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3e", value);
  ::testing::Test::RecordProperty(key, text);
  std::printf("  %-36s %s\n", key, text);
}

M3 matrix_of(double w, double x, double y, double z) {  // unit quaternion → rotation, written out here
  return M3{V3{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
            V3{2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
            V3{2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
}

struct Error {
  double position, angle;
};
// Angle between two rotations from ‖R1 − R2‖_F = 2√2·sin(θ/2): well conditioned for small θ, unlike acos of
// the trace. The estimate's quaternion is renormalised in double first (float leaves |q| − 1 ~ 1e-7, which
// the trace would read as ~6e-4 rad).
template <class T>
Error error_of(const Pose<T>& est, const V3& pos, const M3& rot) {
  const double w = static_cast<double>(est.orientation.w), x = static_cast<double>(est.orientation.x),
               y = static_cast<double>(est.orientation.y), z = static_cast<double>(est.orientation.z);
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  const M3 r = matrix_of(w / n, x / n, y / n, z / n);
  double frob2 = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) frob2 += (r[i][j] - rot[i][j]) * (r[i][j] - rot[i][j]);
  const V3 p{static_cast<double>(est.position.x), static_cast<double>(est.position.y),
             static_cast<double>(est.position.z)};
  return {spidar_ref::len3(spidar_ref::sub(p, pos)), 2 * std::asin(std::min(1.0, std::sqrt(frob2 / 8)))};
}

template <class T>
void true_lengths(const spidar_ref::Device& dev, const V3& pos, const M3& rot, T (&out)[kStrings]) {
  const spidar_ref::Strings s = spidar_ref::strings_at(dev, pos, rot);
  for (int i = 0; i < kStrings; ++i) out[i] = static_cast<T>(s.length[i]);
}

TEST(SpidarPose, CalibrationGivesGeometricRestLengths) {
  const Frame<double> frame = x3_frame<double>();
  const spidar_ref::Device dev = spidar_ref::x3_device();
  const spidar_ref::Strings rest = spidar_ref::strings_at(dev, V3{0, 0, 0}, spidar_ref::axis_angle({0, 1, 0}, 0));
  // Counters anywhere, including next to the 32-bit wrap.
  const std::int32_t at_rest[kStrings] = {0, 17, -5000, 123456, INT32_MAX - 5, INT32_MIN + 3, -1, 999};
  LengthCalibration<double> cal;
  cal.calibrate(frame, at_rest, kQuantum);
  double lengths[kStrings];
  cal.lengths(at_rest, lengths);
  for (int i = 0; i < kStrings; ++i) EXPECT_NEAR(lengths[i], rest.length[i], 1e-15) << i;
  // 10 counts of pay-out on every string, across the wrap for strings 4 and 5.
  std::int32_t moved[kStrings];
  for (int i = 0; i < kStrings; ++i) moved[i] = static_cast<std::int32_t>(static_cast<std::uint32_t>(at_rest[i]) + 10u);
  cal.lengths(moved, lengths);
  for (int i = 0; i < kStrings; ++i) EXPECT_NEAR(lengths[i], rest.length[i] + 10 * kQuantum, 1e-15) << i;
  // At the rest lengths the estimate sits at the centre in the rest orientation and stays there.
  PoseEstimator<double> est;
  est.reset();
  cal.lengths(at_rest, lengths);
  for (int tick = 0; tick < 5; ++tick) EXPECT_EQ(est.update(frame, lengths, PoseParams<double>{}), 0);
  const Error e = error_of(est.pose(), V3{0, 0, 0}, spidar_ref::axis_angle({0, 1, 0}, 0));
  EXPECT_LT(e.position, 1e-15);
  EXPECT_LT(e.angle, 1e-15);
  EXPECT_LT(est.residual_rms(), 1e-15);
}

// From the calibration pose to random poses across the workspace with exact lengths: errors after each tick
// of 2 Gauss–Newton iterations. σ damps the weak rotation block, so rotation converges over a few ticks.
template <class T>
void converge_from_rest(T pos_tol, T angle_tol, const char* label) {
  const Frame<T> frame = x3_frame<T>();
  const spidar_ref::Device dev = spidar_ref::x3_device();
  std::mt19937_64 rng(77);
  constexpr int kTicks = 12;
  double worst_pos[kTicks] = {}, worst_angle[kTicks] = {};
  for (int k = 0; k < 2000; ++k) {
    const spidar_ref::RandomPose truth = spidar_ref::random_pose(rng, 1.0, 0.5);
    T lengths[kStrings];
    true_lengths(dev, truth.pos, truth.rot, lengths);
    PoseEstimator<T> est;
    est.reset();
    for (int tick = 0; tick < kTicks; ++tick) {
      const Flags f = est.update(frame, lengths, PoseParams<T>{});
      ASSERT_FALSE(f & (flag::invalid_input | flag::ill_conditioned)) << k;
      const Error e = error_of(est.pose(), truth.pos, truth.rot);
      worst_pos[tick] = std::max(worst_pos[tick], e.position);
      worst_angle[tick] = std::max(worst_angle[tick], e.angle);
    }
  }
  std::printf("%s: from rest to random poses (workspace, ≤ 29°), exact lengths, worst over 2000:\n", label);
  for (int tick : {0, 1, 2, 4, 7, 11}) {
    char key[64];
    std::snprintf(key, sizeof key, "tick%02d_position_m", tick + 1);
    record(key, worst_pos[tick]);
    std::snprintf(key, sizeof key, "tick%02d_angle_rad", tick + 1);
    record(key, worst_angle[tick]);
  }
  EXPECT_LT(worst_pos[kTicks - 1], static_cast<double>(pos_tol));
  EXPECT_LT(worst_angle[kTicks - 1], static_cast<double>(angle_tol));
}
// Measured: double 4e-17 m / 3e-15 rad, float 3e-8 m / 2e-6 rad (float rounding of the lengths).
TEST(SpidarPose, ConvergesFromRestDouble) { converge_from_rest<double>(1e-12, 1e-12, "double"); }
TEST(SpidarPose, ConvergesFromRestFloat) { converge_from_rest<float>(1e-7f, 1e-5f, "float"); }

// Warm-started tracking of a moving grip (up to ~0.3 m/s and ~3 rad/s), exact lengths, 2 iterations per tick.
template <class T>
void track(double pos_tol, double angle_tol, const char* label) {
  const Frame<T> frame = x3_frame<T>();
  const spidar_ref::Device dev = spidar_ref::x3_device();
  PoseEstimator<T> est;
  est.reset();
  double worst_pos = 0, worst_angle = 0;
  for (int n = 0; n < 20000; ++n) {
    const double t = n * 1e-3;
    const V3 pos{0.03 * std::sin(3.1 * t), 0.045 * std::sin(2.3 * t + 1), 0.03 * std::cos(4.1 * t)};
    const double a = 0.1 * std::sin(2 * spidar_ref::kPi * 4 * t);
    const M3 rot = spidar_ref::multiply(spidar_ref::axis_angle({0.48, 0.6, 0.64}, 0.35 * std::sin(1.7 * t)),
                                        spidar_ref::axis_angle({0, 0, 1}, a));
    T lengths[kStrings];
    true_lengths(dev, pos, rot, lengths);
    est.update(frame, lengths, PoseParams<T>{});
    if (n < 20) continue;  // the start is the calibration pose, not the trajectory's
    const Error e = error_of(est.pose(), pos, rot);
    worst_pos = std::max(worst_pos, e.position);
    worst_angle = std::max(worst_angle, e.angle);
  }
  std::printf("%s: tracking a moving grip for 20 s:\n", label);
  record("max_position_error_m", worst_pos);
  record("max_angle_error_rad", worst_angle);
  EXPECT_LT(worst_pos, pos_tol);
  EXPECT_LT(worst_angle, angle_tol);
}
// Measured: double 7e-10 m / 1.5e-7 rad (the lag of one tick's motion after two Newton steps), float 3e-8 m / 3e-6 rad.
TEST(SpidarPose, TracksMovingGripDouble) { track<double>(1e-8, 1e-6, "double"); }
TEST(SpidarPose, TracksMovingGripFloat) { track<float>(1e-7, 1e-5, "float"); }

// Lengths quantised like the encoder (15.3 µm per count), through the calibration, static random poses.
TEST(SpidarPose, QuantisedLengths) {
  const Frame<float> frame = x3_frame<float>();
  const spidar_ref::Device dev = spidar_ref::x3_device();
  const spidar_ref::Strings rest = spidar_ref::strings_at(dev, V3{0, 0, 0}, spidar_ref::axis_angle({0, 1, 0}, 0));
  const std::int32_t zero[kStrings] = {};
  LengthCalibration<float> cal;
  cal.calibrate(frame, zero, static_cast<float>(kQuantum));
  std::mt19937_64 rng(3);
  double worst_pos = 0, worst_angle = 0, sum_pos2 = 0, sum_angle2 = 0;
  constexpr int kCases = 2000;
  for (int k = 0; k < kCases; ++k) {
    const spidar_ref::RandomPose truth = spidar_ref::random_pose(rng, 1.0, 0.5);
    const spidar_ref::Strings s = spidar_ref::strings_at(dev, truth.pos, truth.rot);
    std::int32_t counts[kStrings];
    for (int i = 0; i < kStrings; ++i)
      counts[i] = static_cast<std::int32_t>(std::lround((s.length[i] - rest.length[i]) / kQuantum));
    float lengths[kStrings];
    cal.lengths(counts, lengths);
    PoseEstimator<float> est;
    est.reset();
    for (int tick = 0; tick < 12; ++tick) est.update(frame, lengths, PoseParams<float>{});
    const Error e = error_of(est.pose(), truth.pos, truth.rot);
    worst_pos = std::max(worst_pos, e.position);
    worst_angle = std::max(worst_angle, e.angle);
    sum_pos2 += e.position * e.position;
    sum_angle2 += e.angle * e.angle;
  }
  std::printf("quantised lengths (%.2f µm per count), float, 2000 static poses, 12 ticks:\n", kQuantum * 1e6);
  record("max_position_error_m", worst_pos);
  record("rms_position_error_m", std::sqrt(sum_pos2 / kCases));
  record("max_angle_error_rad", worst_angle);
  record("rms_angle_error_rad", std::sqrt(sum_angle2 / kCases));
  // Up to half a count (7.7 µm) of error per string: the position is found to about one quantum (measured
  // 13.7 µm max, 5.6 µm rms); the orientation through the 22.5 mm lever to ~quantum/G (measured 1.1 mrad max).
  EXPECT_LT(worst_pos, 2 * kQuantum);
  EXPECT_LT(worst_angle, 2e-3);
}

TEST(SpidarPose, BadLengthsKeepThePoseBounded) {
  const Frame<float> frame = x3_frame<float>();
  const PoseParams<float> params;
  PoseEstimator<float> est;
  est.reset();
  float lengths[kStrings];
  rest_lengths(frame, lengths);
  lengths[2] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(est.update(frame, lengths, params) & flag::invalid_input);
  EXPECT_EQ(est.pose().position.x, 0.0f);
  EXPECT_EQ(est.pose().orientation.w, 1.0f);

  // Lengths no pose can produce (every string 1 m): the estimate is clamped to the frame, finite, flagged.
  for (float& l : lengths) l = 1.0f;
  Flags f = 0;
  for (int tick = 0; tick < 50; ++tick) f |= est.update(frame, lengths, params);
  EXPECT_TRUE(f & flag::pose_limited);
  const Vec3<float> local = frame.workspace_axes.transposed_times(est.pose().position);
  EXPECT_LE(std::fabs(local.x), frame.workspace_half.x + params.position_margin + 1e-6f);
  EXPECT_LE(std::fabs(local.y), frame.workspace_half.y + params.position_margin + 1e-6f);
  EXPECT_LE(std::fabs(local.z), frame.workspace_half.z + params.position_margin + 1e-6f);
  const Quat<float>& q = est.pose().orientation;
  EXPECT_NEAR(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z, 1.0f, 1e-5f);

  // A grip turned 150°: the estimate stops at the 90° limit instead of wrapping the strings.
  const spidar_ref::Device dev = spidar_ref::x3_device();
  true_lengths(dev, V3{0, 0, 0}, spidar_ref::axis_angle({0, 1, 0}, 2.6), lengths);
  est.reset();
  f = 0;
  for (int tick = 0; tick < 50; ++tick) f |= est.update(frame, lengths, params);
  EXPECT_TRUE(f & flag::pose_limited);
  EXPECT_GE(est.pose().orientation.w, params.cos_half_max_angle - 1e-6f);
}

}  // namespace
