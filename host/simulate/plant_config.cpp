#include "host/simulate/plant_config.hpp"

#include <fmt/format.h>

#include "host/common/error.hpp"
#include "host/common/number_text.hpp"

namespace hmp::simulate {

namespace plant = sim::plant;

namespace {

double checked(double value, const std::string& what, double least = 0) {
  if (!(value > 0 && value <= config::kMaxPlantValue))
    throw BadInput(fmt::format("{}: must be positive and at most {} (got {:g})", what,
                               short_number(config::kMaxPlantValue), value));
  if (value < least)
    throw BadInput(fmt::format("{}: must be at least {} (got {:g})", what, short_number(least), value));
  return value;
}

plant::Method method_named(const std::string& name, const std::string& what) {
  plant::Method m{};
  if (!plant::parse_method(name, m)) throw BadInput(what + " " + name + ": unknown (" + integrator_names() + ")");
  return m;
}

}  // namespace

std::string integrator_names() {
  std::string out;
  for (plant::Method m : plant::kAllMethods) out += (out.empty() ? "" : ", ") + std::string(plant::method_name(m));
  return out;
}

void apply_plant_settings(const config::PlantConfig& c, const PlantOverrides& o, plant::PlantParams& p) {
  // The config's values were range-checked when it was read.
  if (c.string_stiffness) p.string.stiffness = *c.string_stiffness;
  if (c.string_damping) p.string.damping = *c.string_damping;
  if (c.grip_mass) p.grip.mass = *c.grip_mass;
  if (c.motor_inertia) p.motor.inertia = *c.motor_inertia;
  if (c.motor_inductance) p.motor.inductance = *c.motor_inductance;
  if (c.finger_stiffness) p.finger.stiffness = *c.finger_stiffness;
  if (c.finger_damping) p.finger.damping = *c.finger_damping;
  if (c.max_step) p.stepper.max_step = *c.max_step;
  if (c.integrator) p.stepper.method = method_named(*c.integrator, "plant.integrator");
  if (o.string_stiffness) p.string.stiffness = checked(*o.string_stiffness, "--string-stiffness");
  if (o.max_step) p.stepper.max_step = checked(*o.max_step, "--max-step", config::kMinMaxStep);
  if (o.integrator) p.stepper.method = method_named(*o.integrator, "--integrator");
}

}  // namespace hmp::simulate
