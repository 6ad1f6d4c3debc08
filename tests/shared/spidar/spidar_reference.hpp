#pragma once
// Double-precision reference SPIDAR-G6 maths for the spidar_* tests, written from design §11 independently of
// shared/spidar/: the X3 table, rotations from axis–angle, string lengths/directions/moment arms, and
// random poses inside the workspace.
#include <array>
#include <cmath>
#include <numbers>
#include <random>

namespace spidar_ref {

using V3 = std::array<double, 3>;
using M3 = std::array<V3, 3>;  // rows

inline V3 add(const V3& a, const V3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline V3 sub(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline V3 scale(double s, const V3& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline double dot3(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline double len3(const V3& a) { return std::sqrt(dot3(a, a)); }
inline V3 cross3(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline V3 mat_vec(const M3& m, const V3& v) { return {dot3(m[0], v), dot3(m[1], v), dot3(m[2], v)}; }
inline M3 multiply(const M3& a, const M3& b) {
  M3 r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
  return r;
}

// Rodrigues: rotation by `angle` about the unit `axis`.
inline M3 axis_angle(const V3& axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle), k = 1 - c;
  const double x = axis[0], y = axis[1], z = axis[2];
  return M3{V3{c + x * x * k, x * y * k - z * s, x * z * k + y * s},
            V3{y * x * k + z * s, c + y * y * k, y * z * k - x * s},
            V3{z * x * k - y * s, z * y * k + x * s, c + z * z * k}};
}
// Rotation angle of a rotation matrix.
inline double angle_of(const M3& r) {
  const double c = std::fmax(-1.0, std::fmin(1.0, (r[0][0] + r[1][1] + r[2][2] - 1) / 2));
  return std::acos(c);
}
inline M3 transpose(const M3& m) {
  return M3{V3{m[0][0], m[1][0], m[2][0]}, V3{m[0][1], m[1][1], m[2][1]}, V3{m[0][2], m[1][2], m[2][2]}};
}

// design §11, X3: PX = PZ = 0.06 m, PY = 0.076 m, grip attachments at ±22.5 mm, whole layout turned −45° about y.
constexpr double kPx = 0.06, kPy = 0.076, kPz = 0.06, kG = 0.0225;
constexpr double kPi = std::numbers::pi;
inline const M3& x3_turn() {
  static const M3 turn = axis_angle({0, 1, 0}, -kPi / 4);
  return turn;
}
struct Device {
  V3 motor[8];
  V3 attach[8];  // grip frame
};
inline Device x3_device() {
  const double corner[8][3] = {{-1, -1, 1}, {1, -1, 1}, {1, -1, -1}, {-1, -1, -1},
                               {-1, 1, 1},  {1, 1, 1},  {1, 1, -1},  {-1, 1, -1}};
  const V3 grip[8] = {{-kG, 0, 0}, {kG, 0, 0}, {0, -kG, 0}, {0, -kG, 0},
                      {-kG, 0, 0}, {kG, 0, 0}, {0, kG, 0},  {0, kG, 0}};
  Device d{};
  for (int i = 0; i < 8; ++i) {
    d.motor[i] = mat_vec(x3_turn(), V3{corner[i][0] * kPx, corner[i][1] * kPy, corner[i][2] * kPz});
    d.attach[i] = mat_vec(x3_turn(), grip[i]);
  }
  return d;
}

struct Strings {
  V3 u[8], m[8];
  double length[8];
};
inline Strings strings_at(const Device& d, const V3& pos, const M3& rot) {
  Strings s{};
  for (int i = 0; i < 8; ++i) {
    const V3 arm = mat_vec(rot, d.attach[i]);
    const V3 diff = sub(d.motor[i], add(pos, arm));
    s.length[i] = len3(diff);
    s.u[i] = scale(1 / s.length[i], diff);
    s.m[i] = cross3(arm, s.u[i]);
  }
  return s;
}

// A grip pose drawn uniformly from `fraction` of the workspace box (motor box shrunk by the grip radius, in
// the turned frame) with a rotation about a random axis by an angle uniform in [0, max_angle].
struct RandomPose {
  V3 pos;
  M3 rot;
  V3 axis;
  double angle;
};
inline RandomPose random_pose(std::mt19937_64& rng, double fraction, double max_angle) {
  std::uniform_real_distribution<double> unit(-1, 1);
  const V3 local{unit(rng) * fraction * (kPx - kG), unit(rng) * fraction * (kPy - kG),
                 unit(rng) * fraction * (kPz - kG)};
  V3 axis;
  do axis = {unit(rng), unit(rng), unit(rng)};
  while (len3(axis) < 0.1 || len3(axis) > 1);
  axis = scale(1 / len3(axis), axis);
  const double angle = std::uniform_real_distribution<double>(0, max_angle)(rng);
  return {mat_vec(x3_turn(), local), axis_angle(axis, angle), axis, angle};
}

}  // namespace spidar_ref
