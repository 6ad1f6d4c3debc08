#include "shared/spidar/motor.hpp"

#include <cmath>
#include <numbers>

namespace hmp::spidar {

template <class T>
MotorModel<T>::MotorModel(const MotorParams<T>& p) {
  // Divisions happen here, once; duty() is two multiply-adds and a clamp.
  const T per_volt = static_cast<T>(1) / p.supply_voltage;
  duty_per_newton_ = p.resistance * p.pulley_radius / p.torque_constant * per_volt;
  duty_per_rad_s_ = (p.resistance * p.viscous_friction / p.torque_constant + p.torque_constant) * per_volt;
  radians_per_count_ = static_cast<T>(2 * std::numbers::pi) / static_cast<T>(p.counts_per_rev);
  metres_per_count_ = radians_per_count_ * p.pulley_radius;
}

template <class T>
T MotorModel<T>::duty(T tension, T omega, Flags& flags) const {
  if (!std::isfinite(tension)) {
    flags |= flag::invalid_input;
    return 0;
  }
  return duty_for_force(tension > 0 ? tension : static_cast<T>(0), omega, flags);  // a string cannot push
}

template <class T>
T MotorModel<T>::duty_checked(T force, T omega, Flags& flags) const {
  if (!std::isfinite(force)) {
    flags |= flag::invalid_input;
    return 0;
  }
  if (!std::isfinite(omega)) {
    flags |= flag::invalid_input;
    omega = 0;
  }
  const T d = force * duty_per_newton_ + omega * duty_per_rad_s_;
  if (d > 1) {
    flags |= flag::saturated;
    return 1;
  }
  if (d < -1) {
    flags |= flag::saturated;
    return -1;
  }
  return d;
}

template class MotorModel<float>;
template class MotorModel<double>;

}  // namespace hmp::spidar
