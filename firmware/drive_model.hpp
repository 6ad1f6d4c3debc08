#pragma once
// Feed-forward compensation of the motor + string + grip dynamics for the SPIDAR drive (docs/spidar.md,
// "Firmware drive"). Stall duties alone do not render a vibration: a motor's rotor (5 g seen from the
// string) on a 10⁴ N/m string resonates at ≈ 225 Hz, and every motor must follow the grip as the
// vibration shakes it (with its inertia and its back-EMF). Neither the string stretch nor the grip's
// vibration is visible to the encoders (15 µm per count), so the drive inverts a model instead:
//
//   motor i   m ẍ_i = (u_i − b ẋ_i)/(1 + τ_e s) − T_i      (u: the voltage's stall force, b = Kt²/(R r²))
//   winding   x_i = x_s,i + (u_i·d) y                      (stretch T/(k + c s), plus following the grip)
//   grip      M ÿ = F − c_h ẏ − k_h y                       (the hand holding it: a nominal spring-damper)
//   ⇒ u_i = T_i + τ_e Ṫ_i + m (ẍ_i + τ_e x⃛_i) + b ẋ_i.
//
// The targets (the QP's tensions, one value per tick) are joined by straight lines from one tick to the
// next and smoothed by a reference model R(s); the derivatives above are exact functions of the models'
// states. A motor command is held for a tick, so the drive sends each command's exact average over the
// coming tick. Along that chain a vibration loses sinc² of its amplitude to the straight lines and sinc²
// to averaging and holding (sinc(πf/f_tick) each); R, a 2nd-order low-pass with ω_c = 2.282/h and
// damping 0.287, is shaped so that |R|·sinc⁴ stays within 0.18% of 1 up to a quarter of the tick rate
// (250 Hz at 1 kHz) and falls beyond it. The rendered force is the target's R-filtered version, delayed
// by about 1.2 ticks. At 1 kHz one more effect shows: the compensator's command has content above the
// tick's Nyquist rate (the inverse of a motor's inertia grows with frequency), and the tick-rate samples
// fold it back into the band (−5.5% at 250 Hz). configure() computes the resulting gain of the whole
// string chain exactly at a design frequency (a quarter of the tick rate, at most 250 Hz) and makes it up
// with a one-tap pre-emphasis of the requested force, (1 + α) F(n) − α F(n−1).
// The back-EMF term uses the model's winding speed, corrected towards the encoders' speed at low
// frequencies (a user moving the grip), where the encoders see the motion well.
#include <cstdint>

#include "shared/spidar/geometry.hpp"
#include "shared/spidar/motor.hpp"

namespace hmp::fw {

// The nominal plant the feed-forward inverts. The defaults are the simulated board's (boards/sim/plant),
// which are estimates for the RE-max 24 class; a real device would have them measured.
struct PlantModel {
  float rotor_inertia = 1.25e-7f;  // J, kg·m² (rotor + pulley)
  float inductance = 0.65e-3f;     // L, H
  float string_stiffness = 1e4f;   // k, N/m
  float string_damping = 2.0f;     // c, N·s/m (> 0; below 1e-3 it is taken as 1e-3)
  float grip_mass = 0.03f;         // M, kg
  float hand_stiffness = 500.0f;   // k_h, N/m: a relaxed pinch
  float hand_damping = 2.0f;       // c_h, N·s/m
};

struct CompensatorConfig {
  bool enabled = true;           // false: plain stall duties + filtered encoder back-EMF (for comparison)
  float speed_blend_hz = 20.0f;  // below this the encoders' speed replaces the model's in the back-EMF term
};

// One model of the compensator, exactly discretised for a tick whose input runs in a straight line from
// last tick's value to this tick's: the state update x(n+1) = Φ x(n) + Γp u(n−1) + Γn u(n), and two
// outputs (motor force, winding speed) averaged over the tick: out = o·x(n) + o_p u(n−1) + o_n u(n).
template <int N>
struct LinearStepper {
  float phi[N][N]{};
  float gamma_prev[N]{}, gamma_now[N]{};
  float force[N]{}, speed[N]{};
  float force_prev = 0.0f, force_now = 0.0f, speed_prev = 0.0f, speed_now = 0.0f;
};

class DriveCompensator {
 public:
  static constexpr int kStrings = spidar::kStrings;
  // R(s) = ω_c²/(s² + 2ζω_c s + ω_c²), ω_c = kReferenceCorner·tick rate: see the header comment.
  static constexpr float kReferenceCorner = 2.282f;
  static constexpr float kReferenceDamping = 0.287f;

  void configure(const PlantModel& plant, const spidar::MotorParams<float>& motor, const CompensatorConfig& config,
                 std::uint32_t tick_hz);
  // At rest with every string at `tension` (N): no motion, no speed correction.
  void reset(float tension);

  // The requested force (N) with the pre-emphasis applied; call once a tick, before the QP.
  float emphasise(float force);

  // One tick. tension: this tick's target tensions (N, the QP's); applied: the force they make along the
  // direction beyond the bias (N); along[i] = u_i·d. measured_speed: the encoders' winding speed over the
  // last tick (rad/s). Out: the force each motor must exert at its pulley (N, may be negative) and the
  // winding speed for its back-EMF (rad/s), both averaged over the coming tick.
  void step(const float (&tension)[kStrings], float applied, const float (&along)[kStrings],
            const float (&measured_speed)[kStrings], float (&motor_force)[kStrings], float (&speed)[kStrings]) {
    advance(tension, applied, along, &measured_speed, motor_force, speed);
  }

  // The split drive (drive.hpp): the encoders' speed comes once a plan period, averaged over it, so it is
  // compared with the model's speed averaged over the same ticks. step_between() is step() without a
  // measurement (the model's speeds are summed); close_window() ends a measurement window (the tick the
  // plan's counts are read); correct(measured) takes the plan's speeds for the window closed last.
  void step_between(const float (&tension)[kStrings], float applied, const float (&along)[kStrings],
                    float (&motor_force)[kStrings], float (&speed)[kStrings]) {
    advance(tension, applied, along, nullptr, motor_force, speed);
  }
  void close_window();
  void correct(const float (&measured_speed)[kStrings], std::uint32_t ticks_per_window);

  bool enabled() const { return config_.enabled; }
  float emphasis() const { return alpha_; }
  // Gain of the string chain (targets → held commands → nominal motor and string) at the design frequency,
  // before the pre-emphasis: 1 without folding.
  float chain_gain() const { return chain_gain_; }

 private:
  // Per string: s = (T_r, Ṫ_r/ω_c, c ẋ_s) at the start of the tick, all in newtons. The third is the
  // string's damper force T_r − k x_s, kept as a state of its own: on stiff strings it is a few parts in
  // 10⁶ of the tension, and the motor force weighs it by m τ_e k²/c³ (6·10⁶ at 10⁷ N/m): T_r − k x_s from
  // two states in float would leave it to rounding.
  struct StringState {
    float s[3]{};
    float last_tension = 0.0f;
    float model_speed = 0.0f;  // the model's winding speed averaged over the last tick (rad/s)
    float correction = 0.0f;   // low-passed (encoder − model) speed (rad/s)
    float window_sum = 0.0f;   // split drive: model speeds summed since the window opened
    float window_mean = 0.0f;  // … and their mean over the window closed last
  };

  void advance(const float (&tension)[kStrings], float applied, const float (&along)[kStrings],
               const float (*measured_speed)[kStrings], float (&motor_force)[kStrings], float (&speed)[kStrings]);

  CompensatorConfig config_{};
  LinearStepper<3> string_{};
  // Grip: g = (F_r, Ḟ_r/ω_c, M ω_c² y, M ω_c ẏ), driven by the applied force; its outputs are the motor
  // force and winding speed per unit of u_i·d.
  LinearStepper<4> grip_model_{};
  float grip_[4]{};
  float last_applied_ = 0.0f;
  StringState strings_[kStrings];
  float alpha_ = 0.0f, last_request_ = 0.0f, chain_gain_ = 1.0f;
  float blend_ = 1.0f;  // speed-correction low-pass coefficient per tick
  float blend_hz_ = 0.0f, tick_hz_ = 1000.0f;
  std::uint32_t window_ticks_ = 0;
  float speed_per_metre_ = 200.0f;  // 1/r
};

}  // namespace hmp::fw
