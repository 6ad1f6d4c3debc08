#pragma once
// Small fixed-size maths for the SPIDAR code: 3-vectors, 3×3 matrices, unit quaternions.
// Templated on the scalar so the firmware runs float while tests and references run double;
// everything is inline and allocation-free.
#include <cmath>

namespace hmp::spidar {

// Laid out by hand (the componentwise operators, one to a line), so the formatter leaves it:
// clang-format off
template <class T>
struct Vec3 {
  T x{}, y{}, z{};

  constexpr Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
  constexpr Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  constexpr Vec3& operator*=(T s) { x *= s; y *= s; z *= s; return *this; }
};

template <class T> constexpr Vec3<T> operator+(Vec3<T> a, const Vec3<T>& b) { return a += b; }
template <class T> constexpr Vec3<T> operator-(Vec3<T> a, const Vec3<T>& b) { return a -= b; }
template <class T> constexpr Vec3<T> operator-(const Vec3<T>& a) { return {-a.x, -a.y, -a.z}; }
template <class T> constexpr Vec3<T> operator*(T s, Vec3<T> a) { return a *= s; }
template <class T> constexpr Vec3<T> operator*(Vec3<T> a, T s) { return a *= s; }

template <class T> constexpr T dot(const Vec3<T>& a, const Vec3<T>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class T> constexpr Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T> constexpr T norm2(const Vec3<T>& a) { return dot(a, a); }
template <class T> T norm(const Vec3<T>& a) { return std::sqrt(norm2(a)); }
template <class T> bool is_finite(const Vec3<T>& a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}
// clang-format on

// Row-major 3×3 matrix; used for rotations (columns are the rotated basis vectors).
template <class T>
struct Mat3 {
  T m[3][3]{};

  static constexpr Mat3 identity() { return Mat3{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}; }
  constexpr Vec3<T> operator*(const Vec3<T>& v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }
  // Mᵀ v: the inverse for a rotation.
  constexpr Vec3<T> transposed_times(const Vec3<T>& v) const {
    return {m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z, m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
            m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z};
  }
};

// Rotation by `angle` radians about the y axis (right-handed: z turns towards x).
template <class T>
Mat3<T> rotation_y(T angle) {
  const T c = std::cos(angle), s = std::sin(angle);
  return Mat3<T>{{{c, 0, s}, {0, 1, 0}, {-s, 0, c}}};
}

// Unit quaternion w + (x, y, z) for the grip's orientation. Kept instead of a matrix because it has four
// numbers to renormalise (cheap drift control) and composes small rotations without trigonometry.
template <class T>
struct Quat {
  T w{1}, x{}, y{}, z{};
};

template <class T>
constexpr Quat<T> operator*(const Quat<T>& a, const Quat<T>& b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

// Rotation matrix of a unit quaternion.
template <class T>
constexpr Mat3<T> to_matrix(const Quat<T>& q) {
  const T xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
  const T xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
  const T wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
  const T one = 1, two = 2;
  return Mat3<T>{{{one - two * (yy + zz), two * (xy - wz), two * (xz + wy)},
                  {two * (xy + wz), one - two * (xx + zz), two * (yz - wx)},
                  {two * (xz - wy), two * (yz + wx), one - two * (xx + yy)}}};
}

}  // namespace hmp::spidar
