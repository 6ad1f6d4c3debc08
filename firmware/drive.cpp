#include "firmware/drive.hpp"
#include "shared/synth/tick_rate.hpp"

#include <cmath>

namespace hmp::fw {

using spidar::Flags;
namespace flag = spidar::flag;

namespace {
constexpr float kTwoPi = 6.28318530717958647692f;
// Pose flags that mean the lengths do not describe a grip the device can hold.
constexpr Flags kPoseBroken = flag::invalid_input | flag::ill_conditioned | flag::pose_limited | flag::short_string;
// QP flags that mean its tensions are not an answer to the request (not_converged is: bounded, nearly optimal).
constexpr Flags kQpBroken = flag::invalid_input | flag::ill_conditioned | flag::degenerate_geometry;
}  // namespace

Drive::Drive(std::uint32_t tick_hz, const DriveParams& params)
    : params_(params),
      tick_hz_(static_cast<float>(tick_hz != 0 ? tick_hz : synth::kNominalTickHz)),
      motor_(params.motor) {
  compensator_.configure(params_.plant, params_.motor, params_.compensator, static_cast<std::uint32_t>(tick_hz_));
  // The sensing runs once a tick, or once a plan in the split drive.
  const std::uint32_t whole = static_cast<std::uint32_t>(tick_hz_);
  if (params_.plan_hz != 0 && params_.plan_hz < whole) ticks_per_plan_ = whole / params_.plan_hz;
  if (params_.plan_hz >= whole) params_.plan_hz = 0;  // as fast as the tick: no split
  sense_hz_ = tick_hz_ / static_cast<float>(ticks_per_plan_);
  // No-load speed V/Ke in counts per sensing period, times the factor; never below 2 counts (quantisation).
  const float no_load = params_.motor.supply_voltage / params_.motor.torque_constant;
  const float counts = params_.limits.jump_speed_factor * no_load * static_cast<float>(params_.motor.counts_per_rev) /
                       kTwoPi / sense_hz_;
  jump_counts_ = counts > 2.0f ? static_cast<std::int32_t>(counts) : 2;
  const float persist = params_.limits.persist_ms * 1e-3f * sense_hz_;
  persist_ticks_ = persist > 1.0f ? static_cast<std::uint16_t>(persist) : 1;
  qp_.max_iterations = params_.qp_max_changes;
  for (float& t : tension_) t = qp_.t_min;
}

void Drive::apply(const protocol::Settings& s) {
  if (!split()) {
    apply_now(s);
    return;
  }
  // The tick writes (plan() never interrupts it); plan() retries a copy that a write overtook.
  staged_seq_.fetch_add(1, std::memory_order_relaxed);  // odd: being written
  std::atomic_thread_fence(std::memory_order_release);
  staged_ = s;
  staged_seq_.fetch_add(1, std::memory_order_release);  // even: complete
}

void Drive::take_staged_settings() {
  for (int tries = 0; tries < 4; ++tries) {
    const std::uint32_t seq = staged_seq_.load(std::memory_order_acquire);
    if (seq == taken_seq_) return;
    if (seq & 1u) continue;
    const protocol::Settings copy = staged_;
    std::atomic_thread_fence(std::memory_order_acquire);
    if (staged_seq_.load(std::memory_order_relaxed) != seq) continue;
    apply_now(copy);
    taken_seq_ = seq;
    return;
  }
}

void Drive::apply_now(const protocol::Settings& s) {
  direction_ = {s.direction[0], s.direction[1], s.direction[2]};
  const float n = spidar::norm(direction_);
  direction_ = n > 0.0f ? (1.0f / n) * direction_ : spidar::Vec3<float>{0.0f, 1.0f, 0.0f};
  peak_n_ = s.peak_force_n;
  qp_.t_min = s.t_min_n;
  qp_.t_max = s.t_max_n;
}

float Drive::hold_duty() const {
  Flags ignored = 0;
  return motor_.duty(qp_.t_min, 0.0f, ignored);  // no back-EMF term: the motors also damp
}

void Drive::hold(float d, float (&duty)[kMotors]) {
  for (int i = 0; i < kMotors; ++i) {
    duty[i] = d;
    tension_[i] = qp_.t_min;
  }
  holding_ = true;
}

// Leaving the safe state: the compensator starts again from strings at rest at t_min.
void Drive::resume() {
  if (!holding_) return;
  compensator_.reset(qp_.t_min);
  holding_ = false;
}

// Encoders → speeds, pose, and the sensing checks. Returns new fault bits.
std::uint32_t Drive::check_sensing(const std::int32_t (&counts)[kMotors], float (&speed)[kMotors], float rate_hz) {
  std::uint32_t faults = 0;
  for (int i = 0; i < kMotors; ++i) {
    // Wrap-around difference: counters may roll over.
    const auto delta =
        static_cast<std::int32_t>(static_cast<std::uint32_t>(counts[i]) - static_cast<std::uint32_t>(last_counts_[i]));
    last_counts_[i] = counts[i];
    if (delta > jump_counts_ || delta < -jump_counts_) {
      faults |= protocol::fault_encoder_jump;
      speed[i] = 0.0f;
    } else {
      speed[i] = motor_.winding_speed(delta, rate_hz);
    }
  }
  float lengths[kMotors];
  calibration_.lengths(counts, lengths);
  const Flags pose_flags = pose_.update(params_.frame, lengths, params_.pose);
  if (pose_flags & kPoseBroken) faults |= protocol::fault_pose_diverged;
  // Misfit: the strings at the last linearisation point (one Gauss–Newton step behind, micrometres while
  // tracking). A slack string has paid out more than its straight path.
  const spidar::StringGeometry<float>& g = pose_.strings();
  bool slack = false;
  for (int i = 0; i < kMotors; ++i) slack = slack || lengths[i] - g.length[i] > params_.limits.slack_m;
  slack_ticks_ = slack ? static_cast<std::uint16_t>(slack_ticks_ + (slack_ticks_ < persist_ticks_)) : 0;
  if (slack_ticks_ >= persist_ticks_) faults |= protocol::fault_string_slack;
  const bool misfit = !(pose_.residual_rms() <= params_.limits.misfit_m);  // NaN counts as a misfit
  misfit_ticks_ = misfit ? static_cast<std::uint16_t>(misfit_ticks_ + (misfit_ticks_ < persist_ticks_)) : 0;
  if (misfit_ticks_ >= persist_ticks_) faults |= protocol::fault_pose_diverged;
  return faults;
}

GripReading Drive::grip_reading(std::uint32_t sensing_faults) const {
  // A pose flagged as diverged (or a misfit that persisted) says nothing about where the hand is.
  if (sensing_faults & protocol::fault_pose_diverged) return {};
  return {pose_.pose().position, true};
}

void Drive::calibrate_once(const std::int32_t (&counts)[kMotors]) {
  if (calibrated_) return;
  calibration_.calibrate(params_.frame, counts, motor_.metres_per_count());
  pose_.reset();
  for (int i = 0; i < kMotors; ++i) last_counts_[i] = counts[i];
  calibrated_ = true;
}

DriveTick Drive::tick(float vibration, bool safe, const std::int32_t (&counts)[kMotors], float (&duty)[kMotors]) {
  DriveTick out;
  calibrate_once(counts);
  float measured[kMotors];
  out.faults = check_sensing(counts, measured, tick_hz_);
  out.grip = grip_reading(out.faults);
  if (safe || out.faults != 0) {
    hold(hold_duty(), duty);
    return out;
  }
  resume();

  // The force: the vibration along the direction, on top of the bias tensions, pre-emphasised for what
  // the tick rate costs (drive_model.hpp). The warm-start bank is keyed by the force asked of the QP: its
  // sign decides which strings sit at t_min.
  const float requested = vibration * peak_n_;
  const float emphasised = compensator_.emphasise(requested);
  const spidar::StringGeometry<float>& strings = pose_.strings();
  const spidar::TensionResult<float> qp =
      spidar::solve_tensions(strings, emphasised * direction_, spidar::Vec3<float>{}, qp_,
                             bank_.at(peak_n_ > 0.0f ? emphasised / peak_n_ : 0.0f));
  out.flags = qp.flags;
  if (qp.flags & kQpBroken) {
    out.faults |= protocol::fault_qp_infeasible;
    hold(hold_duty(), duty);
    return out;
  }
  // What the tensions make along the direction: the QP's force (the bias alone makes ~1 mN, the
  // regulariser's), short of the request where t_max or t_min got in the way.
  const float applied = spidar::dot(qp.force, direction_);
  out.force_n = requested + (applied - emphasised);
  float along[kMotors], motor_force[kMotors], speed[kMotors];
  for (int i = 0; i < kMotors; ++i) {
    tension_[i] = qp.tension[i];
    along[i] = spidar::dot(strings.u[i], direction_);
  }
  compensator_.step(tension_, applied, along, measured, motor_force, speed);
  Flags motor_flags = 0;
  for (int i = 0; i < kMotors; ++i) duty[i] = motor_.duty_for_force(motor_force[i], speed[i], motor_flags);
  out.flags = static_cast<Flags>(out.flags | motor_flags);
  return out;
}

void Drive::plan(const PlanInput& in, DrivePlan& out) {
  take_staged_settings();
  calibrate_once(in.counts);
  out.faults = check_sensing(in.counts, out.speed, sense_hz_);
  out.grip = grip_reading(out.faults);
  out.flags = 0;
  out.hold_duty = hold_duty();
  out.hold = in.safe || out.faults != 0;
  if (out.hold) return;
  const spidar::StringGeometry<float>& strings = pose_.strings();
  out.force_max = params_.plan_headroom * peak_n_;
  // Bias, then the largest force each way: three QPs, each warm-started from its own bank entry.
  const spidar::TensionResult<float> base =
      spidar::solve_tensions(strings, spidar::Vec3<float>{}, spidar::Vec3<float>{}, qp_, bank_.at(0.0f));
  const spidar::TensionResult<float> up = spidar::solve_tensions(
      strings, out.force_max * direction_, spidar::Vec3<float>{}, qp_, bank_.at(params_.plan_headroom));
  const spidar::TensionResult<float> down = spidar::solve_tensions(
      strings, -out.force_max * direction_, spidar::Vec3<float>{}, qp_, bank_.at(-params_.plan_headroom));
  out.flags = static_cast<Flags>(base.flags | up.flags | down.flags);
  if (out.flags & kQpBroken) {
    out.faults |= protocol::fault_qp_infeasible;
    out.hold = true;
    return;
  }
  const float applied_base = spidar::dot(base.force, direction_);
  out.applied_up = spidar::dot(up.force, direction_) - applied_base;
  out.applied_down = spidar::dot(down.force, direction_) - applied_base;
  for (int i = 0; i < kMotors; ++i) {
    out.base[i] = base.tension[i];
    out.up[i] = up.tension[i] - base.tension[i];
    out.down[i] = down.tension[i] - base.tension[i];
    out.along[i] = spidar::dot(strings.u[i], direction_);
  }
}

void Drive::close_speed_window() { compensator_.close_window(); }
void Drive::take_plan_speeds(const DrivePlan& plan) {
  if (!plan.hold && !holding_) compensator_.correct(plan.speed, ticks_per_plan_);
}

DriveTick Drive::render(float vibration, bool safe, const DrivePlan& plan, float (&duty)[kMotors]) {
  DriveTick out;
  out.flags = plan.flags;
  out.grip = plan.grip;
  if (safe || plan.hold || !(plan.force_max > 0.0f)) {
    hold(plan.hold_duty, duty);  // the plan's: no motor model in the tick
    return out;
  }
  resume();
  const float requested = vibration * peak_n_;
  const float emphasised = compensator_.emphasise(requested);
  // Where on the planned line: s ∈ [−1, 1] of force_max (beyond it the set is clamped: saturated).
  float s = emphasised / plan.force_max;
  if (s > 1.0f || s < -1.0f) {
    s = s > 1.0f ? 1.0f : -1.0f;
    out.flags = static_cast<Flags>(out.flags | flag::saturated);
  }
  const float a = s >= 0.0f ? s : -s;
  const float(&delta)[kMotors] = s >= 0.0f ? plan.up : plan.down;
  // (1 − a)·base + a·(base + delta): between two QP answers, both within [t_min, t_max], so within too.
  for (int i = 0; i < kMotors; ++i) tension_[i] = plan.base[i] + a * delta[i];
  const float applied = a * (s >= 0.0f ? plan.applied_up : plan.applied_down);
  out.force_n = requested + (applied - emphasised);
  float motor_force[kMotors], speed[kMotors];
  compensator_.step_between(tension_, applied, plan.along, motor_force, speed);
  Flags motor_flags = 0;
  for (int i = 0; i < kMotors; ++i) duty[i] = motor_.duty_for_force(motor_force[i], speed[i], motor_flags);
  out.flags = static_cast<Flags>(out.flags | motor_flags);
  return out;
}

}  // namespace hmp::fw
