// The drive and the plant at the extremes (design §12): string stiffness 10³–10⁶ N/m, slack strings, saturated
// motors, a 10 kHz tick. The default integrator must stay stable through all of them; an explicit method
// past its stable step must be detected and reported (Plant::unstable, the board's log), never give
// plausible-looking numbers silently.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "tests/firmware/drive/drive_rig.hpp"

namespace hmp::test {
namespace {

sim::SimOptions with_stiffness(double k, bool model_knows) {
  sim::SimOptions o;
  o.plant = sim::PlantOptions{};
  o.plant->params.string.stiffness = k;
  if (model_knows) o.drive.plant.string_stiffness = static_cast<float>(k);
  return o;
}

bool logged(const sim::SimDevice& dev, const std::string& what) {
  return std::any_of(dev.log().begin(), dev.log().end(),
                     [&](const std::string& l) { return l.find(what) != std::string::npos; });
}

// Stiffness from soft line to steel wire. The drive's model is told the stiffness (a calibrated device):
// it still follows; told nothing (the default 10⁴ N/m), it is off but the simulation stays sound.
TEST(DriveExtremes, StringStiffnessRangeStaysStable) {
  for (double k : {1e3, 1e5, 1e6}) {
    for (bool model_knows : {true, false}) {
      const ToneResult r = measure_tone(1000, 100.0, 1.0, with_stiffness(k, model_knows), exact_settings(), 0.15, 0.1);
      char what[64];
      std::snprintf(what, sizeof what, "k = %.0e N/m, model %s", k, model_knows ? "matched" : "10^4");
      print_tone(what, 100.0, r);
      EXPECT_FALSE(r.unstable) << what;
      EXPECT_TRUE(std::isfinite(r.actual)) << what;
      if (model_knows) {
        EXPECT_LE(std::fabs(r.error), 0.05) << what;
        EXPECT_TRUE(r.taut) << what;
        EXPECT_EQ(r.faults, 0u) << what;
      }
    }
  }
}

// t_min = 0: the bias no longer keeps the strings taut; with a vibration on top strings go slack and snap
// taut again. The integrator stays stable and a slack string carries exactly nothing.
TEST(DriveExtremes, SlackStringsStayStable) {
  protocol::Settings s = exact_settings();
  s.t_min_n = 0.0f;
  sim::SimOptions o;
  o.plant = sim::PlantOptions{};
  o.plant->bias_tension = 0.0;
  DriveRig rig(1000, 4, o);
  bool saw_slack = false, slack_carries_nothing = true;
  rig.dev.set_plant_observer([&](double, const sim::plant::PlantOutput& out) {
    for (int i = 0; i < 8; ++i) {
      if (!(out.taut & (1u << i))) {
        saw_slack = true;
        slack_carries_nothing = slack_carries_nothing && out.tension[i] == 0.0;
      }
    }
  });
  rig.start(s);
  rig.tone(rig.dev.tick() + 5, 600, 150.0, 1.0);
  rig.run(600, s.peak_force_n, false);
  EXPECT_TRUE(saw_slack);
  EXPECT_TRUE(slack_carries_nothing);
  EXPECT_FALSE(rig.dev.plant_unstable());
}

// Past what 12 V can do: a 20 N peak with t_max 20 N saturates the duties. Counted, bounded, stable.
TEST(DriveExtremes, SaturatedMotorsStayStable) {
  protocol::Settings s = exact_settings();
  s.peak_force_n = 20.0f;
  s.t_max_n = most_tension_n();
  DriveRig rig(1000, 4);
  double worst = 0;
  rig.dev.set_plant_observer([&](double, const sim::plant::PlantOutput& out) {
    for (double t : out.tension) worst = std::max(worst, t);
  });
  rig.start(s);
  rig.tone(rig.dev.tick() + 5, 500, 100.0, 1.0);
  rig.run(500, s.peak_force_n, false);
  EXPECT_GT(rig.dev.core().stats().drive_saturated, 0u);
  for (float d : rig.dev.duties()) EXPECT_LE(std::fabs(d), 1.0f);
  EXPECT_FALSE(rig.dev.plant_unstable());
  EXPECT_TRUE(std::isfinite(worst));
  // Stall tension at 12 V is 7.86 N; with the motors' own dynamics a string can see somewhat more, never
  // anything unphysical.
  EXPECT_LT(worst, 20.0);
}

// An explicit method past its stable step (explicit Euler at 1 ms, 5× its 0.2 ms limit) is caught: the
// plant flags itself unstable and freezes, the board logs it once, nothing is silently wrong.
TEST(DriveExtremes, ExplicitMethodPastItsLimitIsReported) {
  for (sim::plant::Method m : {sim::plant::Method::explicit_euler, sim::plant::Method::rk4}) {
    sim::SimOptions o;
    o.plant = sim::PlantOptions{};
    o.plant->params.stepper.method = m;
    o.plant->params.stepper.max_step = 1e-3;
    DriveRig rig(1000, 1, o);
    rig.start(exact_settings());
    rig.tone(rig.dev.tick() + 5, 300, 100.0, 1.0);
    rig.run(300, 1.0, false);
    EXPECT_TRUE(rig.dev.plant_unstable()) << static_cast<int>(m);
    EXPECT_TRUE(logged(rig.dev, "plant unstable")) << static_cast<int>(m);
  }
  // The same methods within their limits are fine: 0.1 ms sub-steps.
  sim::SimOptions o;
  o.plant = sim::PlantOptions{};
  o.plant->params.stepper.method = sim::plant::Method::rk4;
  o.plant->params.stepper.max_step = 1e-4;
  const ToneResult r = measure_tone(1000, 100.0, 1.0, o, exact_settings(), 0.1, 0.1);
  EXPECT_FALSE(r.unstable);
  EXPECT_LE(std::fabs(r.error), 0.05);
}

// The default integrator at a 10 kHz tick (one 0.1 ms step per tick) with the stiffest strings.
TEST(DriveExtremes, TenKilohertzTickWithStiffStrings) {
  const ToneResult r = measure_tone(10000, 250.0, 1.0, with_stiffness(1e6, true), exact_settings(), 0.1, 0.1);
  print_tone("10 kHz tick, k = 1e6", 250.0, r);
  EXPECT_FALSE(r.unstable);
  EXPECT_LE(std::fabs(r.error), 0.05);
  EXPECT_TRUE(r.taut);
}

}  // namespace
}  // namespace hmp::test
