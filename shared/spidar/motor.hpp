#pragma once
// String tension → PWM duty for one SPIDAR motor (design §11, Maxon RE-max 24 class), from the DC motor's
// steady state (design §12's equations with di/dt = dω/dt = 0):
//
//   torque balance   Kt·i = r·T + b·ω          (r pulley radius, T tension, b viscous friction)
//   voltage          V = R·i + Ke·ω            (Ke = Kt in SI units)
//   duty             d = V / V_supply, clamped to [−1, 1]
//
// ω is the pulley speed in the winding direction (positive reels string in), estimated from the encoder.
// Back-EMF compensation: a motor winding in needs more voltage for the same current, one being pulled out
// by the user needs less (even a negative duty when pulled fast). The electrical time constant L/R ≈ 0.1 ms
// is far below a 1 ms tick, so the steady-state current is reached within the tick.
#include <cstdint>

#include "shared/spidar/geometry.hpp"

namespace hmp::spidar {

template <class T>
struct MotorParams {
  T torque_constant = static_cast<T>(0.0213);  // Kt, N·m/A; numerically also the back-EMF constant, V·s/rad
  T resistance = static_cast<T>(6.5);          // terminal resistance, Ω
  T supply_voltage = static_cast<T>(12.0);     // V at duty 1
  T pulley_radius = static_cast<T>(0.005);     // m
  T viscous_friction = 0;                      // b, N·m·s/rad (0: not compensated)
  std::int32_t counts_per_rev = 2048;          // 512-line encoder, ×4 quadrature decoding
};

template <class T>
class MotorModel {
 public:
  explicit MotorModel(const MotorParams<T>& params = {});

  // Duty in [−1, 1] that holds `tension` (N, negative treated as 0: a string cannot push) while the pulley
  // winds at `omega` (rad/s). Sets flag::saturated when clamped, flag::invalid_input (and returns 0 — no
  // drive) for a non-finite tension; a non-finite omega drops the back-EMF term and flags invalid_input.
  T duty(T tension, T omega, Flags& flags) const;
  // The same with a signed force at the pulley instead of a string tension: the firmware drive's
  // feed-forward asks the motor for its tension plus what accelerates its own rotor, which may be negative
  // (a motor braking its inertia). Clamping and flags as duty(). Inline for the common case (the firmware
  // calls it for eight motors every tick): an in-range duty needs both inputs finite, so anything else —
  // saturation, NaN, infinities — goes the checked way.
  T duty_for_force(T force, T omega, Flags& flags) const {
    const T d = force * duty_per_newton_ + omega * duty_per_rad_s_;
    if (d >= static_cast<T>(-1) && d <= static_cast<T>(1)) return d;
    return duty_checked(force, omega, flags);
  }

  // Winding speed from one tick's encoder change (counts grow as string pays out, hence the minus sign).
  T winding_speed(std::int32_t delta_counts, T tick_hz) const {
    return -static_cast<T>(delta_counts) * radians_per_count_ * tick_hz;
  }
  T metres_per_count() const { return metres_per_count_; }
  T duty_checked(T force, T omega, Flags& flags) const;
  // Largest tension the supply can hold at standstill (N).
  T stall_tension() const { return static_cast<T>(1) / duty_per_newton_; }

 private:
  T duty_per_newton_;  // R·r / (Kt·V)
  T duty_per_rad_s_;   // (R·b/Kt + Ke) / V
  T radians_per_count_;
  T metres_per_count_;
};

}  // namespace hmp::spidar
