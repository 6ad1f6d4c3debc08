#pragma once
// calibration: the 1 mm set-up of the 2015 paper (§6.1) on the simulated device with its plant. The
// reference vibration is a sine at full scale; the force of full scale (Settings.peak_force_n) is set
// so that the grip moves the target peak displacement. No I/O here: cli/calibrate_command.cpp parses
// the options, prints and writes the config.
//
// Why only `sim`: a real device reports its grip pose in Status, 100 times a second while playing, too
// slowly to see a 50–250 Hz vibration (Nyquist); the plant's grip position is read directly instead.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "boards/sim/sim_device.hpp"
#include "shared/protocol/protocol.hpp"

namespace hmp::simulate {

inline constexpr double kBandLowHz = 50.0, kBandHighHz = 250.0;  // the paper's vibration band
inline constexpr auto kMaxPeakForceN = static_cast<double>(protocol::kMaxPeakForceN);

struct CalibrationSetup {
  std::uint32_t tick_hz = 1000;
  std::array<double, 3> direction{0.0, 1.0, 0.0};      // the config's [device] direction
  sim::plant::PlantParams plant = sim::drive_scene();  // the simulated device's, with the config's [plant]
  double settle_s = 0.2;                               // from the note's start until the transients died down
  double window_s = 0.2;                               // the measured stretch after it
};

// The grip's steady motion under a full-scale sine.
struct GripMotion {
  double hz = 0, peak_force_n = 0;
  double displacement_m = 0;  // amplitude of the grip's f-Hz motion along the direction
  double force_n = 0;         // amplitude of the strings' f-Hz force on the grip along it
  double planned_n = 0;       // largest force the drive's tensions make (Status.force_n): the QP's cap
  bool saturated = false;     // the drive clamped a motor's duty to ±1 in the window
  std::uint32_t faults = 0;   // the device's latched faults (then the vibration was cut)
};

// Plays `hz` at full scale with `peak_force_n` on a fresh simulated device with the plant and measures.
// Throws std::runtime_error when the plant simulation goes unstable.
GripMotion measure_grip(const CalibrationSetup& setup, double hz, double peak_force_n);

// The band's frequencies every 25 Hz: 50, 75, … 250.
std::vector<double> band_frequencies();
// The largest displacement at `hz`: at kMaxPeakForceN, or, when a fault (a string gone slack, the pose
// lost) stops the device there, at the largest force without one, found by bisection to 1 %.
GripMotion reach(const CalibrationSetup& setup, double hz);
std::vector<GripMotion> reach_band(const CalibrationSetup& setup);  // reach() at band_frequencies()

struct Calibration {
  bool reached = false;             // the last step is within `tolerance` of the target
  double peak_force_n = 0;          // the force of full scale of the last step
  std::vector<GripMotion> steps;    // every measurement at a trial force, in order
  std::optional<GripMotion> limit;  // reach(), when a step would pass it (then found once)
  bool out_of_reach() const { return !reached && limit.has_value(); }
};

// Finds the peak force whose displacement at `hz` is `target_m` within `tolerance` (relative): starts at
// 1 N, scales the force by target / measured (displacement is about linear in force) and measures again,
// at most eight times. A force past the reach (or a fault) looks for the reach; below the target there,
// the target is out of reach.
Calibration calibrate(const CalibrationSetup& setup, double hz, double target_m, double tolerance = 0.01);

}  // namespace hmp::simulate
