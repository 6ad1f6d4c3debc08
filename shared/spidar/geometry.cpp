#include "shared/spidar/geometry.hpp"

#include <cmath>

namespace hmp::spidar {

namespace {

// design §11 X3 pairs: motor corner signs (x, y, z) and the grip axis each string ties to.
struct X3String {
  signed char sx, sy, sz;  // motor corner
  signed char gx, gy;      // attachment: ±grip on the grip's x or y axis
};
constexpr X3String kX3[kStrings] = {
    {-1, -1, +1, -1, 0}, {+1, -1, +1, +1, 0}, {+1, -1, -1, 0, -1}, {-1, -1, -1, 0, -1},
    {-1, +1, +1, -1, 0}, {+1, +1, +1, +1, 0}, {+1, +1, -1, 0, +1}, {-1, +1, -1, 0, +1},
};

template <class T>
T sign(signed char s) {
  return static_cast<T>(s);
}

// det(G) ≥ ratio·(trace/3)³ for G = Σ v vᵀ; false also for an all-zero G.
template <class T>
bool spans_space(const Vec3<T> (&v)[kStrings], T ratio) {
  T xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;
  for (int i = 0; i < kStrings; ++i) {
    xx += v[i].x * v[i].x;
    yy += v[i].y * v[i].y;
    zz += v[i].z * v[i].z;
    xy += v[i].x * v[i].y;
    xz += v[i].x * v[i].z;
    yz += v[i].y * v[i].z;
  }
  const T det = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
  const T mean = (xx + yy + zz) / static_cast<T>(3);
  return mean > 0 && det >= ratio * mean * mean * mean;  // NaN fails both comparisons → not spanning
}

}  // namespace

template <class T>
Frame<T> x3_frame(T px, T py, T pz, T grip, T yaw) {
  Frame<T> f;
  const Mat3<T> turn = rotation_y(yaw);
  for (int i = 0; i < kStrings; ++i) {
    const X3String& s = kX3[i];
    f.motor_exit[i] = turn * Vec3<T>{sign<T>(s.sx) * px, sign<T>(s.sy) * py, sign<T>(s.sz) * pz};
    f.attachment[i] = turn * Vec3<T>{sign<T>(s.gx) * grip, sign<T>(s.gy) * grip, 0};
  }
  f.workspace_axes = turn;
  f.workspace_half = {px - grip, py - grip, pz - grip};
  return f;
}

template <class T>
void compute_strings(const Frame<T>& frame, const Vec3<T>& position, const Mat3<T>& rotation, StringGeometry<T>& out) {
  out.flags = 0;
  const T min_length = frame.min_string_length;
  for (int i = 0; i < kStrings; ++i) {
    const Vec3<T> arm = rotation * frame.attachment[i];
    const Vec3<T> d = frame.motor_exit[i] - (position + arm);
    const T length = norm(d);
    out.length[i] = length;
    if (length >= min_length) {  // false for NaN too
      const T inv = static_cast<T>(1) / length;
      out.u[i] = d * inv;
      out.m[i] = cross(arm, out.u[i]);
    } else {
      // A string this short has no usable direction: it contributes nothing to the wrench.
      out.u[i] = {};
      out.m[i] = {};
      out.flags |= std::isfinite(length) ? flag::short_string : flag::invalid_input;
      if (!std::isfinite(length)) out.length[i] = 0;
    }
  }
  if (!inside_workspace(frame, position)) out.flags |= flag::outside_workspace;
}

template <class T>
void rest_lengths(const Frame<T>& frame, T (&lengths)[kStrings]) {
  for (int i = 0; i < kStrings; ++i) lengths[i] = norm(frame.motor_exit[i] - frame.attachment[i]);
}

template <class T>
bool inside_workspace(const Frame<T>& frame, const Vec3<T>& position) {
  const Vec3<T> local = frame.workspace_axes.transposed_times(position);
  return std::fabs(local.x) <= frame.workspace_half.x && std::fabs(local.y) <= frame.workspace_half.y &&
         std::fabs(local.z) <= frame.workspace_half.z;
}

template <class T>
Flags conditioning_flags(const StringGeometry<T>& strings, T ratio) {
  const bool ok = spans_space(strings.u, ratio) && spans_space(strings.m, ratio);
  return ok ? 0 : flag::degenerate_geometry;
}

#define HMP_SPIDAR_GEOMETRY(T)                                                                           \
  template Frame<T> x3_frame<T>(T, T, T, T, T);                                                          \
  template void compute_strings<T>(const Frame<T>&, const Vec3<T>&, const Mat3<T>&, StringGeometry<T>&); \
  template void rest_lengths<T>(const Frame<T>&, T(&)[kStrings]);                                        \
  template bool inside_workspace<T>(const Frame<T>&, const Vec3<T>&);                                    \
  template Flags conditioning_flags<T>(const StringGeometry<T>&, T);
HMP_SPIDAR_GEOMETRY(float)
HMP_SPIDAR_GEOMETRY(double)
#undef HMP_SPIDAR_GEOMETRY

}  // namespace hmp::spidar
