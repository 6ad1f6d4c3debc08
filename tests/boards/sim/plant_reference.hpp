#pragma once
// Independent double-precision facts for the plant_* tests, written from design §11/§12 (not from
// boards/sim/plant): the motor's stall tension and no-load speed, the finger law, and the static balance
// of the grip computed with tests/shared/spidar/spidar_reference.hpp's geometry.
#include <array>
#include <cmath>

#include "tests/shared/spidar/spidar_reference.hpp"

namespace plant_ref {

using spidar_ref::V3;

// RE-max 24 class (design §11): Kt = Ke = 21.3 mN·m/A, R = 6.5 Ω, 12 V, pulley radius 5 mm.
constexpr double kKt = 0.0213, kR = 6.5, kSupply = 12.0, kRadius = 0.005;

// At standstill the back-EMF vanishes: i = V/R, and the torque balance Kt·i = r·T gives T.
inline double stall_tension(double duty) { return kKt * duty * kSupply / (kR * kRadius); }
// With no string load (and no friction) the motor spins until Ke·ω = V.
inline double no_load_speed(double duty) { return duty * kSupply / kKt; }

// Net force on a grip held by a finger spring at `anchor`, strings at the given tensions, at rest.
inline V3 static_force(const spidar_ref::Device& d, const V3& pos, const spidar_ref::M3& rot,
                       const double (&tension)[8], double finger_k, const V3& anchor, double mass, const V3& gravity) {
  const spidar_ref::Strings s = spidar_ref::strings_at(d, pos, rot);
  V3 f = spidar_ref::scale(mass, gravity);
  for (int i = 0; i < 8; ++i) f = spidar_ref::add(f, spidar_ref::scale(tension[i], s.u[i]));
  return spidar_ref::sub(f, spidar_ref::scale(finger_k, spidar_ref::sub(pos, anchor)));
}

// Newton's method (finite-difference Jacobian, Gaussian elimination) for the position where the grip,
// kept in its rest orientation, is in balance.
inline V3 balance_position(const spidar_ref::Device& d, const double (&tension)[8], double finger_k, const V3& anchor,
                           double mass, const V3& gravity) {
  const spidar_ref::M3 identity{V3{1, 0, 0}, V3{0, 1, 0}, V3{0, 0, 1}};
  V3 x = anchor;
  for (int it = 0; it < 50; ++it) {
    const V3 f = static_force(d, x, identity, tension, finger_k, anchor, mass, gravity);
    double a[3][4];
    for (int j = 0; j < 3; ++j) {
      V3 xp = x;
      xp[j] += 1e-7;
      const V3 fp = static_force(d, xp, identity, tension, finger_k, anchor, mass, gravity);
      for (int i = 0; i < 3; ++i) a[i][j] = (fp[i] - f[i]) / 1e-7;
    }
    for (int i = 0; i < 3; ++i) a[i][3] = -f[i];
    for (int k = 0; k < 3; ++k) {
      int p = k;
      for (int i = k + 1; i < 3; ++i)
        if (std::fabs(a[i][k]) > std::fabs(a[p][k])) p = i;
      for (int j = 0; j < 4; ++j) std::swap(a[k][j], a[p][j]);
      for (int i = k + 1; i < 3; ++i) {
        const double l = a[i][k] / a[k][k];
        for (int j = k; j < 4; ++j) a[i][j] -= l * a[k][j];
      }
    }
    V3 dx{};
    for (int i = 2; i >= 0; --i) {
      double s = a[i][3];
      for (int j = i + 1; j < 3; ++j) s -= a[i][j] * dx[j];
      dx[i] = s / a[i][i];
    }
    x = spidar_ref::add(x, dx);
    if (spidar_ref::len3(dx) < 1e-15) break;
  }
  return x;
}

// Rotation matrix of a unit quaternion (w, x, y, z), via its axis and angle.
inline spidar_ref::M3 rotation_of(double w, double x, double y, double z) {
  const double s = std::sqrt(x * x + y * y + z * z);
  if (s == 0) return spidar_ref::M3{V3{1, 0, 0}, V3{0, 1, 0}, V3{0, 0, 1}};
  return spidar_ref::axis_angle({x / s, y / s, z / s}, 2 * std::atan2(s, w));
}

}  // namespace plant_ref
