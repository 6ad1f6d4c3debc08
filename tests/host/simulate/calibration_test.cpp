// host/simulate/calibration: the grip displacement measured on the simulated plant against a model
// computed here, the calibrated force reproducing the target, a target out of reach refused, and the
// config edit keeping everything but the one key.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>

#include "boards/sim/sim_device.hpp"
#include "host/common/error.hpp"
#include "host/simulate/calibration.hpp"

namespace {

namespace sim = hmp::simulate;

// The grip as a mass on the finger's spring and damper, driven by the commanded force: the drive
// controls the string tensions (its compensator cancels the motors' inertia, back-EMF and the string
// spring, docs/spidar.md "Firmware drive"), so the strings act as a force source and add no stiffness.
//   |X| = F / |k_f − M ω² + i ω c_f|
double model_displacement(double hz, double force_n) {
  const hmp::sim::plant::PlantParams p = hmp::sim::drive_scene();
  const double w = 2.0 * M_PI * hz;
  const std::complex<double> z(p.finger.stiffness - p.grip.mass * w * w, w * p.finger.damping);
  return force_n / std::abs(z);
}

TEST(Calibration, DisplacementAgreesWithTheMassSpringModel) {
  for (double hz : {50.0, 100.0, 175.0, 250.0}) {
    const sim::GripMotion g = sim::measure_grip({}, hz, 2.0);
    const double model = model_displacement(hz, 2.0);
    std::printf("%5.0f Hz, 2 N: measured %.4f mm (force %.3f N), model %.4f mm\n", hz, g.displacement_m * 1e3,
                g.force_n, model * 1e3);
    EXPECT_NEAR(g.displacement_m / model, 1.0, 0.10) << hz << " Hz";
    EXPECT_EQ(g.faults, 0u);
  }
}

TEST(Calibration, TheCalibratedForceReproducesTheTarget) {
  const sim::Calibration c = sim::calibrate({}, 100.0, 1e-3);
  ASSERT_TRUE(c.reached);
  ASSERT_GE(c.steps.size(), 2u) << "the first guess is confirmed by measuring again";
  std::printf("100 Hz, 1 mm: %.3f N after %zu measurements\n", c.peak_force_n, c.steps.size());
  const sim::GripMotion again = sim::measure_grip({}, 100.0, c.peak_force_n);
  EXPECT_NEAR(again.displacement_m, 1e-3, 0.03e-3);
  EXPECT_NEAR(c.peak_force_n, 1e-3 / model_displacement(100.0, 1.0), 0.1 * c.peak_force_n);
}

TEST(Calibration, ATargetOutOfReachIsRefused) {
  const sim::Calibration c = sim::calibrate({}, 250.0, 1e-3);
  EXPECT_FALSE(c.reached);
  ASSERT_TRUE(c.out_of_reach());
  EXPECT_LE(c.limit->peak_force_n, sim::kMaxPeakForceN);
  EXPECT_LT(c.limit->displacement_m, 1e-3);
}

}  // namespace

namespace {

// The most the protocol's 20 N can do falls with frequency (the grip's mass) and stays below the model
// (what the drive cannot render: the QP's t_max, duties clamped at ±1).
TEST(Calibration, ReachFallsAcrossTheBand) {
  double last = 1.0;
  for (const sim::GripMotion& g : sim::reach_band({})) {
    std::printf("%5.0f Hz at %g N: %.3f mm (force %.2f N, planned %.2f N%s, faults 0x%x), model %.3f mm\n", g.hz,
                g.peak_force_n, g.displacement_m * 1e3, g.force_n, g.planned_n, g.saturated ? ", saturated" : "",
                g.faults, model_displacement(g.hz, g.peak_force_n) * 1e3);
    EXPECT_LT(g.displacement_m, last) << g.hz << " Hz";
    EXPECT_LE(g.displacement_m, 1.1 * model_displacement(g.hz, g.peak_force_n));
    last = g.displacement_m;
  }
}

}  // namespace
