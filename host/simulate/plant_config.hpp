#pragma once
// The simulated plant's parameters from the user's config ([plant], config/config.hpp) and the command
// line: what lets a user check their own device's strings, masses and damping with `hmp sim`.
#include <optional>
#include <string>

#include "boards/sim/plant/plant_params.hpp"
#include "host/config/config.hpp"

namespace hmp::simulate {

// The command line's plant options; each overrides the config's.
struct PlantOverrides {
  std::optional<double> string_stiffness;  // N/m
  std::optional<double> max_step;          // s
  std::optional<std::string> integrator;   // a Method's name
};

// Applies the config's [plant] values, then the overrides, to `params`. Throws BadInput naming the option
// for a value that is not positive and finite or beyond config::kMaxPlantValue, a max step below
// config::kMinMaxStep, or an unknown integrator.
void apply_plant_settings(const config::PlantConfig& config, const PlantOverrides& overrides,
                          sim::plant::PlantParams& params);

// "explicit_euler, …, exponential": the integrators' names for messages.
std::string integrator_names();

}  // namespace hmp::simulate
