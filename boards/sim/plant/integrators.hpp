#pragma once
// Time integrators for the plant simulator (design §12: at least four, one interface). The plant is stiff
// (string stiffness ~10⁴ N/m against grams of moving mass, electrical time constant ~0.1 ms): explicit
// methods need sub-steps of ~0.1 ms or less, the linearly implicit ones stay stable at the 1 ms tick.
//
//   explicit_euler         y += h·f(y)                                            order 1, explicit
//   semi_implicit_euler    velocities (and currents) first, then positions from     order 1, symplectic
//                          the new velocities                                      for the mechanics
//   rk4                    classical Runge–Kutta                                   order 4, explicit
//   linear_implicit_euler  (I − hJ)·k = f(y), y += h·k                              order 1, L-stable
//   rosenbrock2            ROS2 (Verwer et al. 1999) with γ = 1 − 1/√2: two        order 2, L-stable
//                          stages, one LU; order 2 for any J, so a Jacobian kept
//                          for several steps (a W-method) costs no order
//   exponential            ETD2 on each smooth piece (exponential.hpp): exact for   order 2, A-stable
//                          the linearised plant, switches located inside the step   (exact on linear)
//
// Memory is allocated once, at construction; step() does not allocate or throw.
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string_view>

namespace hmp::sim::plant {

// 8 motors × (angle, speed, current) + grip position, orientation quaternion, velocity, angular velocity,
// + 6 states that observe the string force (the plant's Scene::band_force).
inline constexpr int kMaxState = 43;
// Switch functions of a piecewise-smooth system (two per string: stretch and spring force).
inline constexpr int kMaxSwitches = 16;
// Components of a linearisation's drift (the grip's displacement and rotation).
inline constexpr int kMaxDrift = 6;

enum class Method : std::uint8_t {
  explicit_euler,
  semi_implicit_euler,
  rk4,
  linear_implicit_euler,
  rosenbrock2,
  exponential
};
inline constexpr Method kAllMethods[] = {
    Method::explicit_euler,        Method::semi_implicit_euler, Method::rk4,
    Method::linear_implicit_euler, Method::rosenbrock2,         Method::exponential};
std::string_view method_name(Method m);
// The step each method takes by default: the exponential integrator is exact while the duty is held, so
// one step per tick of up to 1 ms; the others need 125 µs to keep a 250 Hz vibration's force error at
// 10⁴ N/m under 1 % (docs/performance.md).
double default_max_step(Method m);
bool parse_method(std::string_view name, Method& out);

// A first-order system y' = f(y) whose states split into positions (angles, positions, orientation) and
// their rates (speeds, currents, velocities): the split is what semi-implicit Euler needs.
class OdeSystem {
 public:
  virtual ~OdeSystem() = default;
  virtual int size() const = 0;
  virtual void derivative(const double* y, double* dydt) = 0;
  // Rates of the position-like states only (from the velocity-like ones in y); other entries untouched.
  virtual void position_rates(const double* y, double* dydt) const = 0;
  virtual bool is_position(int index) const = 0;
  // Typical magnitude of state `index`: sets the finite-difference step of the numerical Jacobian.
  virtual double scale(int index) const = 0;
  // The function whose Jacobian the linearly implicit methods use. A model with switches (a string going
  // slack) may smooth them out here: those methods need only an approximation of ∂f/∂y, and one that
  // does not jump when a switch flips can be kept for many steps.
  virtual void smooth_derivative(const double* y, double* dydt) { derivative(y, dydt); }
  // Identifies which smoothing smooth_derivative() applies around the state of the last derivative()
  // call; a Jacobian taken under another key is stale.
  virtual std::uint32_t structure_key() const { return 0; }
  // Brings a state back onto its manifold after a step (unit quaternion).
  virtual void project(double* y) const = 0;

  // ---- piecewise-smooth structure (the exponential integrator) ----
  // A model whose right-hand side is smooth between switches (a string going slack) names the smooth piece
  // a state is on: its switch functions g (at most kMaxSwitches; the piece changes only where one of them
  // changes sign), the piece those signs select, and the derivative of one piece extended beyond its
  // borders. The default is one piece everywhere.
  virtual int switch_functions(const double* y, double* g) const {
    (void)y, (void)g;
    return 0;
  }
  virtual std::uint32_t piece_of(const double* g) const {
    (void)g;
    return 0;
  }
  virtual void piece_derivative(const double* y, std::uint32_t piece, double* dydt) {
    (void)piece;
    derivative(y, dydt);
  }
  // The leading states that make up the system; the rest, if any, only observe it (filters of its outputs
  // that feed nothing back), and no step-size decision should follow them.
  virtual int coupled_size() const { return size(); }
  // How far state y has moved from `origin` as the model's nonlinearity sees it: up to kMaxDrift
  // components (returned: how many) in units where a vector of length 1 is as far as a linearisation taken
  // at `origin` may be used. 0 components: the model is linear on each piece. A model may stop early and
  // return −1 once the squared length of the components so far exceeds `beyond` (y is farther than that).
  virtual int linearisation_drift(const double* origin, const double* y, double* drift,
                                  double beyond = kNoBound) const {
    (void)origin, (void)y, (void)drift, (void)beyond;
    return 0;
  }
  static constexpr double kNoBound = std::numeric_limits<double>::infinity();
  // How far ahead of a moving state, along its motion, a new linearisation may be taken, in the drift's
  // units (0: at the state). One taken ahead serves the way ahead as well as the state.
  virtual double linearisation_lead() const { return 0; }
  // An upper bound on the angular frequency (rad/s) at which the switch functions can ring: how closely
  // a step must be followed for a switch function that crosses zero and comes back to be seen. 0: none
  // known (the checkpoints of the exponential integrator are taken to suffice).
  virtual double switch_frequency() const { return 0; }

  // ---- coordinates in which the model is nearly linear (the exponential integrator) ----
  // A model whose stiff part is linear in other coordinates z = Φ(y) than its own (a string's stretch in
  // place of its motor's angle: the stretch's tension is linear in it, where the angle's goes through the
  // string's curved geometric length) maps states both ways and derivatives forward, dz/dt = DΦ(y)·dy/dt.
  // Φ must keep the pose-like states that linearisation_drift() and project() read. The default is none.
  virtual bool has_linear_coordinates() const { return false; }
  virtual void to_linear(const double* y, double* z) const { (void)y, (void)z; }
  virtual void from_linear(const double* z, double* y) const { (void)z, (void)y; }
  // dzdt = DΦ(y)·dydt; dzdt may be dydt itself.
  virtual void linear_rates(const double* y, const double* dydt, double* dzdt) const {
    (void)y, (void)dydt, (void)dzdt;
  }
  // scale() of z's states.
  virtual double linear_scale(int index) const { return scale(index); }
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  virtual Method method() const = 0;
  // Advances y by h in place.
  virtual void step(OdeSystem& system, double* y, double h) = 0;
  // Forget any cached Jacobian (after a reset or a parameter change).
  virtual void invalidate() {}
  // Derivative evaluations so far (Jacobian columns included): the work measure of the benchmark.
  std::uint64_t evaluations() const { return evaluations_; }
  std::uint64_t factorisations() const { return factorisations_; }

 protected:
  std::uint64_t evaluations_ = 0;
  std::uint64_t factorisations_ = 0;
};

struct IntegratorOptions {
  // Simulated time a Jacobian is reused by the linearly implicit methods (at least one step).
  double jacobian_max_age = 8e-3;  // s
};

std::unique_ptr<Integrator> make_integrator(Method method, const IntegratorOptions& options = {});

// The classical Runge–Kutta step, shared by Method::rk4 and the exponential integrator's short explicit
// sub-steps: y advances by h from k1 = f(y), given; three derivative evaluations, the state projected at
// the end only.
struct RungeKuttaWork {
  std::array<double, kMaxState> k2{}, k3{}, k4{}, stage{};
};
void rk4_step(OdeSystem& system, double* y, double h, const double* k1, RungeKuttaWork& work);

}  // namespace hmp::sim::plant
