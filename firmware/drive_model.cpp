#include "firmware/drive_model.hpp"

#include <cmath>

#include "shared/spidar/matrix_exp.hpp"
#include "shared/synth/tick_rate.hpp"

namespace hmp::fw {

namespace {

constexpr float kPi = 3.14159265358979f;

// configure() computes in double and keeps float coefficients for the tick. With stiff strings the string
// part is stiff: its stretch follows the tension within c/k (0.2 µs at 10⁷ N/m), A·h reaches thousands,
// and the motor force holds m τ_e k²/c³ (6·10⁶ at 10⁷ N/m) times the damper's force c ẋ_s, a few parts in
// 10⁶ of the tension. Computed in float, the rounding of those rows and of the exponential's sums left the
// motor force at rest 0.32 × the target at 10⁷ N/m (0.88 × at 3·10⁶).
using Real = double;

// The model's continuous quantities. configure() derives the output rows by evaluating these formulas on
// unit states (they stay readable; the tick runs only the resulting dot products).
struct Constants {
  Real wc, zeta, m, tau_e, k, c, grip_mass, kh, ch;
};

// Motor force without the back-EMF term, and the winding speed, for the string part at state s
// (T_r, Ṫ_r/ω_c, c ẋ_s) with R's input at `target`.
void string_outputs(const Constants& q, const Real (&s)[3], Real target, Real& force, Real& speed) {
  const Real t_dot = q.wc * s[1];
  const Real t_ddot = q.wc * q.wc * (target - s[0]) - 2 * q.zeta * q.wc * q.wc * s[1];
  const Real x_dot = s[2] / q.c;
  const Real x_ddot = (t_dot - q.k * x_dot) / q.c;
  const Real x_dddot = (t_ddot - q.k * x_ddot) / q.c;
  force = s[0] + q.tau_e * t_dot + q.m * (x_ddot + q.tau_e * x_dddot);
  speed = x_dot;
}

// The same for the grip part at state g (F_r, Ḟ_r/ω_c, M ω_c² y, M ω_c ẏ), per unit of u_i·d.
void grip_outputs(const Constants& q, const Real (&g)[4], Real& force, Real& speed) {
  const Real y = g[2] / (q.grip_mass * q.wc * q.wc);
  const Real y_dot = g[3] / (q.grip_mass * q.wc);
  const Real f_dot = q.wc * g[1];
  const Real y_ddot = (g[0] - q.ch * y_dot - q.kh * y) / q.grip_mass;
  const Real y_dddot = (f_dot - q.ch * y_ddot - q.kh * y_dot) / q.grip_mass;
  force = q.m * (y_ddot + q.tau_e * y_dddot);
  speed = y_dot;
}

// One tick of x' = A x + B w with w running from w(n−1) to w(n), and the integrals of the two outputs
// o·x + o_in·w, from the exponential of the augmented system (x, w, w's slope, ∫force, ∫speed).
template <int N>
LinearStepper<N> make_stepper(const Real (&a)[N][N], const Real (&b)[N], const Real (&force)[N], Real force_in,
                              const Real (&speed)[N], Real speed_in, Real h) {
  constexpr int W = N, P = N + 1, QF = N + 2, QV = N + 3, M = N + 4;
  Real am[M][M]{};
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j < N; ++j) am[i][j] = a[i][j];
    am[i][W] = b[i];
    am[QF][i] = force[i];
    am[QV][i] = speed[i];
  }
  am[W][P] = 1 / h;  // w' = (w(n) − w(n−1))/h, the slope state holding w(n) − w(n−1)
  am[QF][W] = force_in;
  am[QV][W] = speed_in;
  Real e[M][M];
  spidar::expm(am, h, e);
  // Start values: w = w(n−1), slope = w(n) − w(n−1).
  const auto f = [](Real v) { return static_cast<float>(v); };
  LinearStepper<N> out;
  const Real inv_h = 1 / h;
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j < N; ++j) out.phi[i][j] = f(e[i][j]);
    out.gamma_prev[i] = f(e[i][W] - e[i][P]);
    out.gamma_now[i] = f(e[i][P]);
    out.force[i] = f(e[QF][i] * inv_h);
    out.speed[i] = f(e[QV][i] * inv_h);
  }
  out.force_prev = f((e[QF][W] - e[QF][P]) * inv_h);
  out.force_now = f(e[QF][P] * inv_h);
  out.speed_prev = f((e[QV][W] - e[QV][P]) * inv_h);
  out.speed_now = f(e[QV][P] * inv_h);
  return out;
}

// Just enough complex arithmetic for the design-frequency check (no <complex>: it drags in streams).
struct Cx {
  Real re = 0, im = 0;
};
Cx operator+(Cx a, Cx b) { return {a.re + b.re, a.im + b.im}; }
Cx operator-(Cx a, Cx b) { return {a.re - b.re, a.im - b.im}; }
Cx operator*(Cx a, Cx b) { return {a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re}; }
Cx operator*(Real s, Cx a) { return {s * a.re, s * a.im}; }
Cx operator/(Cx a, Cx b) {
  const Real d = b.re * b.re + b.im * b.im;
  return {(a.re * b.re + a.im * b.im) / d, (a.im * b.re - a.re * b.im) / d};
}
Real abs(Cx a) { return std::sqrt(a.re * a.re + a.im * a.im); }

// The discrete response of a stepper's two outputs to u(n) = e^{jθn}: x = (e^{jθ} − Φ)⁻¹(Γp e^{−jθ} + Γn),
// out = o·x + o_p e^{−jθ} + o_n (Gaussian elimination with partial pivoting on the complex 3×3). It reads
// the float coefficients the tick runs, in double like the rest of configure().
void stepper_response(const LinearStepper<3>& s, Real theta, Cx& force, Cx& speed) {
  const auto d = [](float v) { return static_cast<Real>(v); };
  const Cx z{std::cos(theta), std::sin(theta)}, zinv{z.re, -z.im};
  Cx m[3][4];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m[i][j] = Cx{(i == j ? z.re : 0) - d(s.phi[i][j]), i == j ? z.im : 0};
    m[i][3] = d(s.gamma_prev[i]) * zinv + Cx{d(s.gamma_now[i]), 0};
  }
  for (int k = 0; k < 3; ++k) {
    int p = k;
    for (int i = k + 1; i < 3; ++i)
      if (abs(m[i][k]) > abs(m[p][k])) p = i;
    for (int j = 0; j < 4; ++j) {
      const Cx t = m[k][j];
      m[k][j] = m[p][j];
      m[p][j] = t;
    }
    for (int i = k + 1; i < 3; ++i) {
      const Cx f = m[i][k] / m[k][k];
      for (int j = k; j < 4; ++j) m[i][j] = m[i][j] - f * m[k][j];
    }
  }
  Cx x[3];
  for (int i = 2; i >= 0; --i) {
    Cx acc = m[i][3];
    for (int j = i + 1; j < 3; ++j) acc = acc - m[i][j] * x[j];
    x[i] = acc / m[i][i];
  }
  force = d(s.force_prev) * zinv + Cx{d(s.force_now), 0};
  speed = d(s.speed_prev) * zinv + Cx{d(s.speed_now), 0};
  for (int i = 0; i < 3; ++i) {
    force = force + d(s.force[i]) * x[i];
    speed = speed + d(s.speed[i]) * x[i];
  }
}

}  // namespace

void DriveCompensator::configure(const PlantModel& plant, const spidar::MotorParams<float>& motor,
                                 const CompensatorConfig& config, std::uint32_t tick_hz) {
  config_ = config;
  const float hz = static_cast<float>(tick_hz != 0 ? tick_hz : synth::kNominalTickHz);
  const float h = 1.0f / hz;
  const float r = motor.pulley_radius;
  speed_per_metre_ = 1.0f / r;
  blend_ = 1.0f - std::exp(-2.0f * kPi * config.speed_blend_hz * h);
  blend_hz_ = config.speed_blend_hz;
  tick_hz_ = hz;

  const auto d = [](float v) { return static_cast<Real>(v); };
  const Real hd = 1 / d(hz), rd = d(r);
  Constants q{};
  q.wc = d(kReferenceCorner) * d(hz);
  q.zeta = d(kReferenceDamping);
  q.m = d(plant.rotor_inertia) / (rd * rd);
  q.tau_e = d(plant.inductance) / d(motor.resistance);
  q.k = d(plant.string_stiffness);
  q.c = d(plant.string_damping > 1e-3f ? plant.string_damping : 1e-3f);
  q.grip_mass = d(plant.grip_mass);
  q.kh = d(plant.hand_stiffness);
  q.ch = d(plant.hand_damping);

  // Strings: s1' = ω_c s2, s2' = ω_c (T − s1) − 2ζ ω_c s2, s3' = ω_c s2 − (k/c) s3 (c ẋ_s = T_r − k x_s).
  const Real a3[3][3] = {{0, q.wc, 0}, {-q.wc, -2 * q.zeta * q.wc, 0}, {0, q.wc, -q.k / q.c}};
  const Real b3[3] = {0, q.wc, 0};
  Real force3[3], speed3[3], force3_in = 0, speed3_in = 0;
  for (int j = 0; j < 3; ++j) {
    Real unit[3] = {};
    unit[j] = 1;
    string_outputs(q, unit, 0, force3[j], speed3[j]);
  }
  const Real zero3[3] = {};
  string_outputs(q, zero3, 1, force3_in, speed3_in);
  string_ = make_stepper(a3, b3, force3, force3_in, speed3, speed3_in, hd);

  // Grip: g1' = ω_c g2, g2' = ω_c (F − g1) − 2ζ ω_c g2, g3' = ω_c g4, g4' = ω_c g1 − (c_h/M) g4 − k_h/(M ω_c) g3.
  const Real a4[4][4] = {{0, q.wc, 0, 0},
                         {-q.wc, -2 * q.zeta * q.wc, 0, 0},
                         {0, 0, 0, q.wc},
                         {q.wc, 0, -q.kh / (q.grip_mass * q.wc), -q.ch / q.grip_mass}};
  const Real b4[4] = {0, q.wc, 0, 0};
  Real force4[4], speed4[4];
  for (int j = 0; j < 4; ++j) {
    Real unit[4] = {};
    unit[j] = 1;
    grip_outputs(q, unit, force4[j], speed4[j]);
  }
  grip_model_ = make_stepper(a4, b4, force4, 0, speed4, 0, hd);

  // The string chain at the design frequency: targets → held commands (force, and speed for the back-EMF)
  // → a motor and string with the grip held still. The plant's response to a held command is the hold's
  // (1 − e^{−jθ})/(jθ) over the model's K(s) = (1 + τ_e s) + (m s²(1 + τ_e s) + b s)/(k + c s).
  Real design_hz = d(0.25f * hz);
  if (design_hz > 250) design_hz = 250;
  const Real pi = d(kPi);
  const Real theta = 2 * pi * design_hz * hd;
  Cx d_force, d_speed;
  stepper_response(string_, theta, d_force, d_speed);
  const Real kt = d(motor.torque_constant);
  const Real b_damp = kt * kt / (d(motor.resistance) * rd * rd);
  const Cx command = d_force + b_damp * d_speed;  // the stepper's speed is ẋ (m/s), b's unit
  const Cx jw{0, 2 * pi * design_hz};
  const Cx lag = Cx{1, 0} + q.tau_e * jw;
  const Cx k_of_s = lag + (q.m * (jw * jw * lag) + b_damp * jw) / (Cx{q.k, 0} + q.c * jw);
  const Cx hold = (Cx{1 - std::cos(theta), std::sin(theta)}) / Cx{0, theta};
  const Real gain = abs(command * hold / k_of_s);
  chain_gain_ = static_cast<float>(gain);
  // |(1 + α) − α e^{−jθ}|² = 1 + 2α(1 + α)(1 − cos θ) = 1/gain²; α may be negative (a chain that gains).
  const Real want = gain > 0 ? 1 / gain : 1;
  const Real cq = (want * want - 1) / (2 * (1 - std::cos(theta)));
  alpha_ = static_cast<float>(cq > -0.25 ? 0.5 * (std::sqrt(1 + 4 * cq) - 1) : -0.5);
  reset(0.0f);
}

float DriveCompensator::emphasise(float force) {
  const float out = config_.enabled ? (1.0f + alpha_) * force - alpha_ * last_request_ : force;
  last_request_ = force;
  return out;
}

void DriveCompensator::reset(float tension) {
  for (StringState& st : strings_) {
    st.s[0] = tension;
    st.s[1] = 0.0f;
    st.s[2] = 0.0f;
    st.last_tension = tension;
    st.model_speed = 0.0f;
    st.correction = 0.0f;
    st.window_sum = 0.0f;
    st.window_mean = 0.0f;
  }
  window_ticks_ = 0;
  for (float& g : grip_) g = 0.0f;
  last_applied_ = 0.0f;
  last_request_ = 0.0f;
}

void DriveCompensator::close_window() {
  const float n = window_ticks_ > 0 ? static_cast<float>(window_ticks_) : 1.0f;
  for (StringState& st : strings_) {
    st.window_mean = st.window_sum / n;
    st.window_sum = 0.0f;
  }
  window_ticks_ = 0;
}

void DriveCompensator::correct(const float (&measured_speed)[kStrings], std::uint32_t ticks_per_window) {
  // The low-pass of step(), at the window's rate.
  const float window_s = static_cast<float>(ticks_per_window != 0 ? ticks_per_window : 1u) / tick_hz_;
  const float blend = 1.0f - std::exp(-2.0f * kPi * blend_hz_ * window_s);
  for (StringState& st : strings_) {
    const float model = config_.enabled ? st.window_mean : 0.0f;
    st.correction += blend * (measured_speed[&st - strings_] - model - st.correction);
  }
}

void DriveCompensator::advance(const float (&tension)[kStrings], float applied, const float (&along)[kStrings],
                               const float (*measured_speed)[kStrings], float (&motor_force)[kStrings],
                               float (&speed)[kStrings]) {
  if (!config_.enabled) {
    // Stall duties; the back-EMF from the encoders' speed, low-passed (their quantum is 3 rad/s at 1 kHz).
    for (int i = 0; i < kStrings; ++i) {
      StringState& st = strings_[i];
      if (measured_speed != nullptr) st.correction += blend_ * ((*measured_speed)[i] - st.correction);
      motor_force[i] = tension[i];
      speed[i] = st.correction;
    }
    return;
  }
  const LinearStepper<4>& gm = grip_model_;
  float grip_force = gm.force_prev * last_applied_ + gm.force_now * applied;
  float grip_speed = gm.speed_prev * last_applied_ + gm.speed_now * applied;
  float g[4];
  for (int i = 0; i < 4; ++i) {
    grip_force += gm.force[i] * grip_[i];
    grip_speed += gm.speed[i] * grip_[i];
    g[i] = gm.gamma_prev[i] * last_applied_ + gm.gamma_now[i] * applied;
    for (int j = 0; j < 4; ++j) g[i] += gm.phi[i][j] * grip_[j];
  }
  for (int i = 0; i < 4; ++i) grip_[i] = g[i];
  last_applied_ = applied;
  if (measured_speed == nullptr) ++window_ticks_;

  // A local copy: the stores into strings_ below cannot alias it, so its coefficients stay in registers
  // instead of being loaded again for every string (measured: ~30 instructions a tick on the M4F).
  const LinearStepper<3> sm = string_;
  for (int i = 0; i < kStrings; ++i) {
    StringState& st = strings_[i];
    const float t = tension[i], tp = st.last_tension;
    const float x[3] = {st.s[0], st.s[1], st.s[2]};
    const float model_speed = speed_per_metre_ * (sm.speed[0] * x[0] + sm.speed[1] * x[1] + sm.speed[2] * x[2] +
                                                  sm.speed_prev * tp + sm.speed_now * t + along[i] * grip_speed);
    motor_force[i] = sm.force[0] * x[0] + sm.force[1] * x[1] + sm.force[2] * x[2] + sm.force_prev * tp +
                     sm.force_now * t + along[i] * grip_force;
    float next[3];
    for (int r = 0; r < 3; ++r) {
      next[r] =
          sm.gamma_prev[r] * tp + sm.gamma_now[r] * t + sm.phi[r][0] * x[0] + sm.phi[r][1] * x[1] + sm.phi[r][2] * x[2];
    }
    st.s[0] = next[0];
    st.s[1] = next[1];
    st.s[2] = next[2];
    st.last_tension = t;
    // measured_speed averages the last tick, as does the model speed kept from the last step.
    if (measured_speed != nullptr) {
      st.correction += blend_ * ((*measured_speed)[i] - st.model_speed - st.correction);
    } else {
      st.window_sum += model_speed;
    }
    st.model_speed = model_speed;
    speed[i] = model_speed + st.correction;
  }
}

}  // namespace hmp::fw
