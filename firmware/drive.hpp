#pragma once
// The SPIDAR-G6 motor drive of the firmware tick (design §8, §11; docs/spidar.md "Firmware drive"):
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
#include <atomic>
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
  // The split drive (below): the rate of its slow part, which must divide the tick rate. 0: no split,
  // the whole drive in every tick.
  std::uint32_t plan_hz = 0;
  // The split drive plans tensions for forces up to this many times the peak force (the pre-emphasis
  // lifts the request above the peak at high frequencies).
  float plan_headroom = 2.0f;
};

// Where the grip is, as this tick's (or plan's) pose estimate says: what the view's cursor follows
// (Status bytes 45–57). Not known while the pose cannot be fitted.
struct GripReading {
  spidar::Vec3<float> position{};  // m, device frame
  bool known = false;
};

// What one tick of the drive tells the core.
struct DriveTick {
  std::uint32_t faults = 0;  // protocol fault bits found this tick (qp_infeasible, pose_diverged, ...)
  float force_n = 0.0f;      // the force along the direction the tensions make, beyond the bias (N)
  spidar::Flags flags = 0;   // pose, QP and motor flags of this tick (saturated, not_converged, ...)
  GripReading grip;
};

// The split drive. At a fast tick (10 kHz on the STM32F407) the whole drive does not fit a tick, but only
// part of it has to run that fast. The slow part, plan() — encoders, the sensing checks, the pose and the
// tension QP — runs at plan_hz outside the tick; it solves the QP for the bias and for the largest force
// either way along the direction and leaves the three tension sets in a DrivePlan. The fast part,
// render() — every tick — turns this tick's vibration into its force, takes the tensions on the line
// between the bias and the planned set of that sign (the QP's answer is linear in the force while the
// same strings sit at their bounds, and clamped to [t_min, t_max] where it is not), and runs the dynamics
// compensation and the motor duties. docs/spidar.md, "Split drive".
struct PlanInput {
  std::int32_t counts[spidar::kStrings]{};
  bool safe = false;  // hold every string at t_min (a latched fault)
};

struct DrivePlan {
  std::uint32_t faults = 0;  // sensing or QP faults found by this plan
  spidar::Flags flags = 0;   // pose and QP flags
  bool hold = true;          // render holds the strings at t_min with stall duties
  float hold_duty = 0.0f;
  float force_max = 0.0f;                        // N: the force of the `up`/`down` sets (0: no plan yet)
  float base[spidar::kStrings]{};                // tensions of the bias (zero force)
  float up[spidar::kStrings]{};                  // tensions for +force_max along the direction, minus base
  float down[spidar::kStrings]{};                // tensions for −force_max, minus base
  float applied_up = 0.0f, applied_down = 0.0f;  // the force those make along the direction, beyond the bias
  float along[spidar::kStrings]{};               // u_i · d
  float speed[spidar::kStrings]{};               // winding speed measured over the last plan period (rad/s)
  GripReading grip;
};

class Drive {
 public:
  static constexpr int kMotors = spidar::kStrings;

  explicit Drive(std::uint32_t tick_hz, const DriveParams& params = {});

  // Direction, peak force and the tension bounds (the protocol has checked their ranges, the core that
  // t_max is at most max_tension_n()). The split drive takes them at its next plan (they are staged: a
  // plan in progress never sees half of them).
  void apply(const protocol::Settings& settings);

  // The most string tension the settings may ask for: a margin under what the motors hold at standstill,
  // so that neither the bias nor the safe state's hold at t_min runs every motor saturated (the
  // protocol's 20 N is far above a 7.9 N stall tension).
  float max_tension_n() const { return kHoldableFraction * motor_.stall_tension(); }
  static constexpr float kHoldableFraction = 0.8f;

  // One tick. `vibration`: this tick's output value (full scale, already limited). `safe`: hold every
  // string at t_min with stall duties (a latched fault). The first call calibrates: the grip is at the
  // centre in its rest orientation (design §11).
  DriveTick tick(float vibration, bool safe, const std::int32_t (&counts)[kMotors], float (&duty)[kMotors]);

  // The split drive (params().plan_hz ≠ 0). plan(): the slow part, outside the tick (it owns the pose,
  // the QP and their warm starts); render(): every tick (it owns the compensator). The two never touch
  // the same state; settings reach plan() through apply() only between plans (the core's job).
  bool split() const { return params_.plan_hz != 0; }
  std::uint32_t ticks_per_plan() const { return ticks_per_plan_; }
  void plan(const PlanInput& in, DrivePlan& out);
  // `safe`: hold at t_min now, without waiting for the next plan (a fault latched since).
  DriveTick render(float vibration, bool safe, const DrivePlan& plan, float (&duty)[kMotors]);
  // The tick the plan's counts are read: the speed window closes. The tick a new plan is first used: its
  // measured speeds correct the model's (DriveCompensator::correct).
  void close_speed_window();
  void take_plan_speeds(const DrivePlan& plan);

  // ---- inspection ----
  bool calibrated() const { return calibrated_; }
  const spidar::Pose<float>& pose() const { return pose_.pose(); }
  // The grip as the last sensing left it, given the faults that sensing found.
  GripReading grip_reading(std::uint32_t sensing_faults) const;
  const float (&tensions() const)[kMotors] { return tension_; }
  const DriveParams& params() const { return params_; }
  const DriveCompensator& compensator() const { return compensator_; }

 private:
  std::uint32_t check_sensing(const std::int32_t (&counts)[kMotors], float (&speed)[kMotors], float rate_hz);
  void calibrate_once(const std::int32_t (&counts)[kMotors]);
  void apply_now(const protocol::Settings& settings);
  void take_staged_settings();
  float hold_duty() const;                     // the stall duty of t_min
  void hold(float d, float (&duty)[kMotors]);  // the safe state: every motor at d, tensions at t_min
  void resume();

  DriveParams params_;
  float tick_hz_;
  float sense_hz_;  // the rate check_sensing runs at: the tick's, or the plan's
  std::uint32_t ticks_per_plan_ = 1;
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
  // Settings for the split drive's next plan: written by the tick, read by plan() with a sequence check.
  protocol::Settings staged_{};
  std::atomic<std::uint32_t> staged_seq_{0};
  std::uint32_t taken_seq_ = 0;
};

}  // namespace hmp::fw
