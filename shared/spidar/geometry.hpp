#pragma once
// SPIDAR-G6 geometry (design §11): where the 8 strings leave their motors, where they tie to the grip, and
// the per-string quantities every other SPIDAR module needs at a given grip pose: length, unit direction
// u_i from the attachment point towards the motor exit, and moment arm m_i = (R b_i) × u_i.
// Device frame: Y up, metres, origin at the frame centre. The grip frame has its origin at the ball centre.
#include <cstdint>

#include "shared/spidar/vec.hpp"

namespace hmp::spidar {

inline constexpr int kStrings = 8;

// Condition flags shared by the geometry, tension, pose and motor code (bitwise or-ed into results).
using Flags = std::uint16_t;
namespace flag {
inline constexpr Flags invalid_input = 1u << 0;  // NaN/Inf in a wrench, a length, a pose or a parameter
inline constexpr Flags short_string = 1u << 1;   // a string shorter than Frame::min_string_length
inline constexpr Flags degenerate_geometry =
    1u << 2;  // strings (nearly) coplanar: some force/torque direction unreachable
inline constexpr Flags outside_workspace = 1u << 3;  // grip centre outside the configured workspace box
inline constexpr Flags not_converged = 1u << 4;      // iteration cap reached before the optimality test passed
inline constexpr Flags ill_conditioned = 1u << 5;    // a Cholesky pivot collapsed (numerically singular system)
inline constexpr Flags pose_limited = 1u << 6;       // pose estimate clamped (rotation > angle limit or left the frame)
inline constexpr Flags saturated = 1u << 7;          // a motor duty clamped to ±1
}  // namespace flag

template <class T>
struct Frame {
  Vec3<T> motor_exit[kStrings];  // string exit point of motor i, device frame
  Vec3<T> attachment[kStrings];  // b_i: where string i ties to the grip, grip frame
  // The box the grip centre may occupy: centred at the origin, axes rotated by workspace_axes (box → device),
  // half extents workspace_half along those axes. Outside it the pose is flagged (strings get short and coplanar).
  Mat3<T> workspace_axes = Mat3<T>::identity();
  Vec3<T> workspace_half{};
  T min_string_length = static_cast<T>(0.002);  // below this a string's direction is meaningless
};

// The "X3" frame (Springhead SpidarG6X3): motors at the corners (±px, ±py, ±pz) of a box, attachment points
// at ±grip on the grip's x and y axes, both turned by `yaw` about y (−45° for the X3 layout). The workspace
// is the motor box shrunk by the grip radius on every side.
template <class T>
Frame<T> x3_frame(T px = static_cast<T>(0.06), T py = static_cast<T>(0.076), T pz = static_cast<T>(0.06),
                  T grip = static_cast<T>(0.0225), T yaw = static_cast<T>(-0.78539816339744830962));

template <class T>
struct Pose {
  Vec3<T> position{};     // grip centre, device frame
  Quat<T> orientation{};  // grip frame → device frame
};

// Everything the tension and pose code needs about the strings at one pose.
template <class T>
struct StringGeometry {
  Vec3<T> u[kStrings];   // unit direction attachment → motor exit (zero for a short string)
  Vec3<T> m[kStrings];   // (R b_i) × u_i: torque about the grip centre per newton of tension (zero if short)
  T length[kStrings]{};  // |motor exit − attachment|
  Flags flags = 0;       // invalid_input, short_string, outside_workspace
};

// Fills `out` for the grip at `pose`; `rotation` is to_matrix(pose.orientation), passed in because callers
// already have it. Short or non-finite strings get u = m = 0 (they take no part in force or pose maths) and
// a flag; a grip centre outside the workspace box sets outside_workspace.
template <class T>
void compute_strings(const Frame<T>& frame, const Vec3<T>& position, const Mat3<T>& rotation, StringGeometry<T>& out);

template <class T>
void compute_strings(const Frame<T>& frame, const Pose<T>& pose, StringGeometry<T>& out) {
  compute_strings(frame, pose.position, to_matrix(pose.orientation), out);
}

// Lengths with the grip at the centre in its rest orientation: what calibration sets (design §11).
template <class T>
void rest_lengths(const Frame<T>& frame, T (&lengths)[kStrings]);

template <class T>
bool inside_workspace(const Frame<T>& frame, const Vec3<T>& position);  // false for NaN

// degenerate_geometry if the strings cannot span all force directions or all torque directions, else 0.
// Test: det(G) < ratio·(trace(G)/3)³ for the force Gram matrix G = Σ u uᵀ or the torque one Σ m mᵀ, i.e. the
// product of G's eigenvalues far below what equal eigenvalues would give (scale-free, no division, ≈ 100
// multiply-adds). Coplanar strings make the force Gram singular; strings through the centre the torque one.
template <class T>
Flags conditioning_flags(const StringGeometry<T>& strings, T ratio);

}  // namespace hmp::spidar
