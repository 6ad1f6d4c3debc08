#pragma once
// The plant scenes the integrators are compared on (design §12; the sim-work-precision benchmark, the
// tests, docs/performance.md): a plant, its bias tension and the duties and finger anchor of every tick,
// fixed in advance so that every integrator and the reference see the same input.
//
//   vibration_<f>hz_<a>n   a vibration of f Hz and a N along y at the centre: each tick the firmware's
//                          tension solver (shared/spidar) at the finger's pose turns the force into
//                          tensions, the motor model into stall duties (strings stay taut)
//   frame_edge             the 250 Hz, 1 N vibration while the finger carries the grip over 0.3 s to 90 %
//                          of the workspace box (x and y of its axes), the duties making up for the
//                          motors' back-EMF as the moving grip winds and pays out the strings
//   slack                  the 250 Hz, 1 N vibration; every 100 ms the drive stops for 40 ms (the strings go
//                          slack, the grip drops onto the finger) and then snaps them taut again
//   saturation             the 250 Hz, 1 N vibration's duty swing ×10, clamped at ±1 (saturated motors,
//                          partly slack strings)
#include <string>
#include <string_view>
#include <vector>

#include "boards/sim/plant/plant_params.hpp"
#include "host/simulate/plant_reference.hpp"

namespace hmp::simulate {

struct PlantScene {
  std::string name;
  sim::plant::PlantParams params;
  double bias_tension = 0.3;  // N, every string at reset
  PlantDrive drive;
};

// Scenes whose strings stay taut (the vibrations and frame_edge) come first; then slack, saturation.
const std::vector<std::string_view>& plant_scene_names();
bool taut_scene(std::string_view name);

// The scene `name` with strings of `stiffness` N/m over `seconds`. Unknown name: BadInput.
PlantScene make_plant_scene(std::string_view name, double stiffness, double seconds);

}  // namespace hmp::simulate
