#pragma once
// The SPIDAR-G6 motor drive of the firmware tick (SPEC §8, §11; docs/spidar.md "Firmware drive"):
//
//   encoders → string lengths (LengthCalibration) → grip pose (PoseEstimator, 1 Gauss–Newton step,
//   warm start) → force F = vibration × peak force × direction → tensions (the QP: every string between
//   t_min and t_max, TensionStateBank warm starts) → motor forces (DriveCompensator: the motor + string +
//   grip dynamics inverted) → PWM duties (MotorModel, back-EMF from the model's and the encoders' speed).
//
// It also watches the sensing: an encoder that jumps, a pose that cannot be fitted, a string that has
// gone slack, a QP that has no sound answer. Such a tick is reported to the core, which latches the fault
// and silences the vibration; the drive then holds every string at t_min with plain stall duties (the
// safe state) until the core lets it go. Freestanding, float, no allocation.
#include <cstdint>

#include "firmware/drive_model.hpp"
#include "shared/protocol/protocol.hpp"
#include "shared/spidar/geometry.hpp"
#include "shared/spidar/motor.hpp"
#include "shared/spidar/pose.hpp"
#include "shared/spidar/tension.hpp"

namespace hmp::fw {

// When the sensing is taken as broken. Each check must hold for `persist_ms` (at least one tick) except the
// encoder jump, which is one reading.
struct DriveLimits {
  // A counter may change per tick by at most this many times what the motor's no-load speed at full
  // supply allows (183 counts per ms for the RE-max 24); anything faster is a glitch or a lost counter.
  float jump_speed_factor = 1.5f;
  // A string whose paid-out length exceeds its straight path by this much is slack (m).
  float slack_m = 1.5e-3f;
  // RMS misfit of the eight lengths to the best pose (m): strings slipped, a counter off, a broken string.
  float misfit_m = 1.0e-3f;
  float persist_ms = 2.0f;
};

// The pose estimator's settings for the drive: one Gauss–Newton step per tick (docs/spidar.md, "Cost on
// the Cortex-M4F": the second step costs ~1,700 instructions and the warm-started estimate tracks to
// nanometres with one).
inline spidar::PoseParams<float> drive_pose_params() {
  spidar::PoseParams<float> p;
  p.iterations = 1;
  return p;
}

struct DriveParams {
  spidar::Frame<float> frame = spidar::x3_frame<float>();
  spidar::MotorParams<float> motor{};
  spidar::PoseParams<float> pose = drive_pose_params();
  // Active-set changes the tension QP may make per tick; over it the answer is polished and flagged
  // not_converged, and the next tick carries on from the set reached (bounds the tick's worst case).
  int qp_max_changes = 2;
  PlantModel plant{};
  CompensatorConfig compensator{};
  DriveLimits limits{};
};

// What one tick of the drive tells the core.
struct DriveTick {
  std::uint32_t faults = 0;  // protocol fault bits found this tick (qp_infeasible, pose_diverged, ...)
  float force_n = 0.0f;      // the force along the direction the tensions make, beyond the bias (N)
  spidar::Flags flags = 0;   // pose, QP and motor flags of this tick (saturated, not_converged, ...)
};

class Drive {
 public:
  static constexpr int kMotors = spidar::kStrings;

  explicit Drive(std::uint32_t tick_hz, const DriveParams& params = {});

  // Direction, peak force and the tension bounds (the protocol has checked their ranges).
  void apply(const protocol::Settings& settings);

  // One tick. `vibration`: this tick's output value (full scale, already limited). `safe`: hold every
  // string at t_min with stall duties (a latched fault). The first call calibrates: the grip is at the
  // centre in its rest orientation (SPEC §11).
  DriveTick tick(float vibration, bool safe, const std::int32_t (&counts)[kMotors], float (&duty)[kMotors]);

  // ---- inspection ----
  bool calibrated() const { return calibrated_; }
  const spidar::Pose<float>& pose() const { return pose_.pose(); }
  const float (&tensions() const)[kMotors] { return tension_; }
  const DriveParams& params() const { return params_; }
  const DriveCompensator& compensator() const { return compensator_; }

 private:
  std::uint32_t check_sensing(const std::int32_t (&counts)[kMotors], float (&speed)[kMotors]);
  void hold(float (&duty)[kMotors]);

  DriveParams params_;
  float tick_hz_;
  spidar::MotorModel<float> motor_;
  spidar::LengthCalibration<float> calibration_{};
  spidar::PoseEstimator<float> pose_{};
  spidar::TensionParams<float> qp_{};
  spidar::TensionStateBank bank_{};
  DriveCompensator compensator_{};
  spidar::Vec3<float> direction_{0.0f, 1.0f, 0.0f};
  float peak_n_ = 1.0f;
  std::int32_t last_counts_[kMotors]{};
  std::int32_t jump_counts_ = 1;
  std::uint16_t persist_ticks_ = 1;
  std::uint16_t slack_ticks_ = 0, misfit_ticks_ = 0;
  float tension_[kMotors]{};
  bool calibrated_ = false;
  bool holding_ = true;  // the compensator is reset when the drive leaves the safe state
};

}  // namespace hmp::fw
