#pragma once
// The plant's equations of motion (design §12) as a first-order system for the integrators.
//
//   motor i:   θ_i' = ω_i                                    θ: pulley angle, positive winds string in
//              J ω_i' = Kt·I_i − r·T_i − b·ω_i
//              L I_i' = V_i − R·I_i − Ke·ω_i                 V_i = duty_i · V_supply
//   string i:  s_i = |p_i − a_i| − (ℓ_i − r·θ_i)             stretch: geometric length minus free length
//              ṡ_i = −u_i·v − m_i·w + r·ω_i
//              T_i = max(0, k·s_i + c·ṡ_i) if s_i > 0, else 0 (a slack string carries nothing)
//   grip:      x' = v,   M v' = Σ T_i u_i + F_finger + M g
//              q' = ½ (0, w) ⊗ q,   I w' = Σ T_i m_i + N_finger     (a ball: isotropic, no gyroscopic term)
//   finger:    F_finger = −k_f (x − anchor) − c_f v,   N_finger = −k_r φ − c_r w   (φ: rotation vector of q)
//   band:      b'' = ω_b² (F − b) − √2 ω_b b'   per axis of F = Σ T_i u_i (Scene::band_force only): b is the
//              string force through a 2nd-order Butterworth low-pass at kBandHz, the part a finger feels
//
// u_i, m_i and lengths come from shared/spidar's compute_strings(), the same code the firmware uses.
// A translation-only scene drops q and w (the grip keeps its rest orientation; torques are still reported).
#include <cstdint>
#include <numbers>

#include "boards/sim/plant/integrators.hpp"
#include "boards/sim/plant/plant_params.hpp"

namespace hmp::sim::plant {

// Index of each block in the state vector.
namespace state {
inline constexpr int angle = 0;              // θ_i, 8
inline constexpr int speed = 8;              // ω_i, 8
inline constexpr int current = 16;           // I_i, 8
inline constexpr int position = 24;          // x, 3
inline constexpr int velocity = 27;          // v, 3
inline constexpr int orientation = 30;       // q (w, x, y, z), 4 — full 6-DOF only
inline constexpr int angular_velocity = 34;  // w, 3 — full 6-DOF only
inline constexpr int translation_size = 30;
inline constexpr int full_size = 37;
inline constexpr int band_size = 6;  // (b, b') per axis, after the rest when Scene::band_force
}  // namespace state

// The band the finger feels (design §12): the cut-off of the string force's low-pass above.
inline constexpr double kBandHz = 1000.0;
inline constexpr double kBandOmega = 2 * std::numbers::pi * kBandHz;  // rad/s

// A slack string this close to taut (m) keeps its spring in the implicit methods' Jacobian: ~ the string
// a motor can reel in within a 1 ms step at full speed (2.8 m/s), so a string never snaps taut under a
// Jacobian that ignores it. Slacker strings drop out of the Jacobian, where a spring that is not there
// would cost accuracy (measured: a free-running motor 0.014% slow at 125 µs steps).
inline constexpr double kJacobianSlackMargin = 5e-3;

// Strings at least this stiff are integrated by the exponential method in stretch coordinates
// (PlantDynamics::to_linear). Chosen by the sim-work-precision benchmark (docs/performance.md): at 10⁶
// and 10⁷ N/m the errors fall (on the same reach, a carried grip's string force at 10⁷ N/m 9.6% → 0.18%,
// the 50 Hz vibration's 0.55% → 0.03%); at 10⁵ N/m, where a tick's path curvature costs the tension
// little, they do not (the carried grip's string force 0.99% → 1.05%, finger 0.15% → 0.23%), and there
// the motors' own coordinates stay.
inline constexpr double kStretchCoordinatesFrom = 1e6;  // N/m

// How far the grip may move from where the exponential integrator linearised the equations before it
// linearises again (see PlantDynamics::linearisation_drift). The strings' ringing is lightly damped and
// fast, and its coupling to the grip turns with the strings' directions, so stiffer strings need a
// closer linearisation: the reach shrinks as √(stiff / k) above `stiff` (in the motors' coordinates; in
// stretch coordinates, kStretchCoordinatesFrom and above, the tensions are linear and it stays 0.5 mm:
// a grip carried 0.3 mm a tick then reuses linearisations, 2.2× the speed of one per tick at 10⁷ N/m for
// 0.40% / 0.18% string / finger force instead of 0.18% / 0.05%), and softer ones allow a longer
// one, growing as √(soft / k) below `soft` (a grip carried across the frame then needs a tenth of the
// linearisations at 10³ N/m). Between the two it stays put: there the strings' slack/taut switching under
// saturated drive is what needs it (at 10⁴ N/m a reach 1.8× longer costs 1.3% of finger force instead of
// 0.4%). Chosen by the sim-work-precision benchmark (docs/performance.md).
//
// A carried grip's new linearisation is taken ahead of it along its motion (linearisation_lead()), `lead`
// of the reach, `stretch_lead` in stretch coordinates: at 10⁵ N/m `frame_edge` then takes 138 instead
// of 183 linearisations for the same errors; at 10⁷ N/m, in stretch coordinates, 0.8 of the reach ahead
// cost 0.57% of finger force (0.18% without a lead), 0.3 costs none (docs/sim-integrator-log.md).
struct LinearDrift {
  double distance = 0.5e-3;   // m
  double angle = 0.01;        // rad
  double stiff = 1e5;         // N/m
  double soft = 1e4;          // N/m
  double lead = 0.8;          // of the reach
  double stretch_lead = 0.3;  // of the reach
};
inline constexpr LinearDrift kLinearDrift{};

// Everything the equations compute on the way to the derivative: what the board and the tests read.
struct PlantForces {
  double tension[spidar::kStrings]{};  // N
  double stretch[spidar::kStrings]{};  // m (negative: slack)
  // k·s_i + c·ṡ_i whatever the signs: the string pulls while this and s_i are both positive. Its zeros and
  // the stretch's are where the right-hand side jumps (what an event-locating solver looks for).
  double spring[spidar::kStrings]{};  // N
  Vec3d string_force{};               // Σ T_i u_i on the grip, N
  Vec3d string_torque{};              // Σ T_i m_i about the grip centre, N·m
  Vec3d finger_force{};               // force of the grip on the finger (zero without a finger), N
  Vec3d finger_torque{};              // torque of the grip on the finger, N·m
  std::uint32_t taut = 0;             // bit i: string i taut (s_i > 0)
  std::uint32_t near_taut = 0;        // bit i: s_i > −kJacobianSlackMargin (see smooth_derivative())
  spidar::Flags geometry_flags = 0;   // short_string / outside_workspace / invalid_input from the geometry
};

class PlantDynamics final : public OdeSystem {
 public:
  explicit PlantDynamics(const PlantParams& params);

  // Free length ℓ_i of each string at θ_i = 0 (set by the plant's reset).
  void set_free_length(int i, double metres) {
    free_length_[i] = metres;
    switches_valid_ = false;
  }
  double free_length(int i) const { return free_length_[i]; }
  void set_voltage(int i, double volts) { voltage_[i] = volts; }
  void set_finger_anchor(const Vec3d& anchor) { anchor_ = anchor; }
  const Vec3d& finger_anchor() const { return anchor_; }
  const PlantParams& params() const { return params_; }
  // The string force's part below kBandHz at state y (zero without Scene::band_force); at_rest: the
  // filter's state for a grip at rest with string force f.
  Vec3d band_force(const double* y) const;
  void set_band_at_rest(double* y, const Vec3d& f) const;

  // Forces at state y (any state of size(); a quaternion need not be unit, it is normalised here).
  // `bilateral`: near-taut strings push as well as pull (see smooth_derivative()).
  void evaluate(const double* y, PlantForces& out, bool bilateral = false) const;

  int size() const override { return size_; }
  int coupled_size() const override { return band_; }  // the band states only observe
  void derivative(const double* y, double* dydt) override;
  void position_rates(const double* y, double* dydt) const override;
  bool is_position(int index) const override;
  double scale(int index) const override;
  // The equations with every string that is taut or nearly so (near_taut) a bilateral spring-damper
  // (T = k·s + c·ṡ whatever its sign): the Jacobian of this does not jump when a string goes slack, and
  // overstating a just-slack string's stiffness only makes the linearly implicit step more implicit than
  // needed. The key is the near_taut mask of the last derivative() call.
  void smooth_derivative(const double* y, double* dydt) override;
  std::uint32_t structure_key() const override { return near_taut_; }
  void project(double* y) const override;

  // Pieces: bit i of a piece is string i pulling (s_i > 0 and k·s_i + c·ṡ_i > 0). The switch functions
  // are the eight stretches, then the eight spring forces; a piece's derivative makes its strings
  // bilateral spring-dampers and the others absent.
  int switch_functions(const double* y, double* g) const override;
  std::uint32_t piece_of(const double* g) const override;
  void piece_derivative(const double* y, std::uint32_t piece, double* dydt) override;
  // The equations are nonlinear in the grip's pose only (string directions and lever arms): the drift
  // is the grip's displacement over kLinearDrift.distance and its rotation vector over kLinearDrift.angle
  // (both shrunk for stiff strings), 3 or 6 components; −1 without the rotation when the displacement
  // alone is beyond `beyond`.
  int linearisation_drift(const double* origin, const double* y, double* drift,
                          double beyond = kNoBound) const override;
  double linearisation_lead() const override {
    return stretch_coordinates_ ? kLinearDrift.stretch_lead : kLinearDrift.lead;
  }
  // Every string taut: ω² ≤ k·(r²/J + n/m + n·R²/I), the stiffness over the masses each string moves
  // (its rotor; the grip's mass and, through lever arms of at most the grip's radius R, its inertia) summed
  // over a row as Gershgorin's bound does. 10,600 rad/s at 10⁵ N/m, 33,700 at 10⁶.
  double switch_frequency() const override { return switch_frequency_; }

  // Stretch coordinates: each motor's angle θ_i replaced by its string's stretch s_i = ℓ_i(pose) − (free
  // length − r·θ_i), the speeds kept (s_i' = r·ω_i − u_i·v − m_i·w). A taut string's tension k·s + c·ṡ is
  // then linear in the state; through the angle it follows the string's geometric length, whose curvature
  // along a carried grip's path a step's linearisation misses by ~k·(v·h)²/(8ℓ): 0.4 N at 10⁷ N/m, 0.3 m/s.
  bool has_linear_coordinates() const override { return stretch_coordinates_; }
  void to_linear(const double* y, double* z) const override;
  void from_linear(const double* z, double* y) const override;
  void linear_rates(const double* y, const double* dydt, double* dzdt) const override;
  double linear_scale(int index) const override;

 private:
  // How each string's tension follows from its spring force k·s + c·ṡ.
  enum class TensionRule : std::uint8_t { unilateral, near_bilateral, piece };
  void compute(const double* y, PlantForces& out, TensionRule rule, std::uint32_t piece) const;
  // The strings' geometry at y's pose (kept while the pose stays the same bit for bit).
  const spidar::StringGeometry<double>& strings_at(const double* y) const;
  void rates(const double* y, double* dydt, TensionRule rule, std::uint32_t piece, std::uint32_t* near_taut) const;

  PlantParams params_;
  int size_;
  int band_;  // index of the band states (size_ without them)
  double free_length_[spidar::kStrings]{};
  double voltage_[spidar::kStrings]{};
  Vec3d anchor_{};
  std::uint32_t near_taut_ = 0;
  // The switch functions of the last state compute() saw: every evaluation computes them on its way, and
  // the integrators ask for them at states they have just differentiated (a step's start and end), so
  // switch_functions() there costs a comparison of states instead of the strings' geometry again.
  mutable double switches_state_[kMaxState]{};
  mutable double switches_[2 * spidar::kStrings]{};
  mutable bool switches_valid_ = false;
  // The strings' geometry at the pose (position, then orientation if any) compute() last saw.
  mutable double geometry_pose_[7]{};
  mutable spidar::Quat<double> geometry_orientation_{};
  mutable spidar::StringGeometry<double> geometry_;
  mutable bool geometry_valid_ = false;
  // Constants of the motor equations, divided once.
  double inv_inductance_, inv_inertia_, inv_mass_, inv_grip_inertia_;
  bool stretch_coordinates_;  // stiff enough to be stepped in stretch coordinates
  double drift_scale_;        // the reach's scale for the strings' stiffness (1 between soft and stiff)
  double switch_frequency_;   // rad/s
};

}  // namespace hmp::sim::plant
