#include "host/simulate/plant_scenes.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "host/common/error.hpp"
#include "shared/spidar/motor.hpp"
#include "shared/spidar/tension.hpp"

namespace hmp::simulate {

namespace {

namespace plant = sim::plant;

constexpr double kTick = 1e-3;  // s: the scenes' control tick
constexpr double kPi = 3.14159265358979323846;

struct Vibration {
  double freq_hz, amplitude_n;
};

spidar::StringGeometry<double> strings_at(const PlantScene& s, std::size_t tick) {
  spidar::StringGeometry<double> g;
  spidar::compute_strings(s.params.frame, s.drive.anchor[tick], spidar::Mat3<double>::identity(), g);
  return g;
}

// Feed-forward duties for a vibration along y rendered at the finger's anchor (the pose the firmware would
// estimate), `gain` times the swing around the bias (gain > 1 drives the duties into saturation). Where the
// anchor moves, each motor's duty also makes up for its back-EMF at the speed the moving grip winds its
// string at, as the firmware drive does: without it the strings a moving grip slackens lose their
// tension (at 0.4 m/s the back-EMF is 1.7 V against the bias's 0.5 V).
void vibration_duties(PlantScene& s, Vibration v, double gain) {
  const spidar::MotorModel<double> motor(s.params.motor.drive);
  const spidar::TensionParams<double> tp;
  spidar::TensionState warm;
  spidar::Flags ignored = 0;
  const double bias = motor.duty(tp.t_min, 0.0, ignored);
  const double r_pulley = s.params.motor.drive.pulley_radius;
  const std::size_t ticks = s.drive.duty.size();
  std::vector<spidar::StringGeometry<double>> geometry(ticks);
  for (std::size_t k = 0; k < ticks; ++k) geometry[k] = strings_at(s, k);
  for (std::size_t k = 0; k < ticks; ++k) {
    const spidar::StringGeometry<double>& g = geometry[k];
    const std::size_t before = k > 0 ? k - 1 : 0, after = std::min(k + 1, ticks - 1);
    const double span = static_cast<double>(after - before) * kTick;
    const double t = static_cast<double>(k) * kTick;
    const spidar::Vec3<double> force{0.0, v.amplitude_n * std::sin(2 * kPi * v.freq_hz * t), 0.0};
    const auto r = spidar::solve_tensions(g, force, spidar::Vec3<double>{}, tp, warm);
    for (int i = 0; i < spidar::kStrings; ++i) {
      // θ' winds the string in: a string the grip shortens is wound in at −L'/r.
      const double omega = span > 0 ? -(geometry[after].length[i] - geometry[before].length[i]) / span / r_pulley : 0.0;
      spidar::Flags f = 0;
      const double still = motor.duty(r.tension[i], 0.0, f);
      const double d = motor.duty(r.tension[i], omega, f);
      // The swing around the bias is scaled by `gain`; the back-EMF term is not.
      s.drive.duty[k][static_cast<std::size_t>(i)] =
          bias + gain * (still - bias) + (d - still);  // clamped by the plant
    }
  }
}

struct VibrationScene {
  std::string_view name;
  Vibration vibration;
};
constexpr VibrationScene kVibrations[] = {{"vibration_250hz_1n", {250, 1.0}},
                                          {"vibration_250hz_0.5n", {250, 0.5}},
                                          {"vibration_50hz_1n", {50, 1.0}},
                                          {"vibration_50hz_0.5n", {50, 0.5}}};
constexpr Vibration kDefaultVibration{250, 1.0};

}  // namespace

const std::vector<std::string_view>& plant_scene_names() {
  static const std::vector<std::string_view> names = [] {
    std::vector<std::string_view> v;
    for (const VibrationScene& s : kVibrations) v.push_back(s.name);
    for (std::string_view s : {"frame_edge", "slack", "saturation"}) v.push_back(s);
    return v;
  }();
  return names;
}

bool taut_scene(std::string_view name) { return name != "slack" && name != "saturation"; }

PlantScene make_plant_scene(std::string_view name, double stiffness, double seconds) {
  if (std::find(plant_scene_names().begin(), plant_scene_names().end(), name) == plant_scene_names().end())
    throw BadInput("plant scene '" + std::string(name) + "': unknown");
  PlantScene s;
  s.name = std::string(name);
  s.params.string.stiffness = stiffness;
  const auto ticks = static_cast<std::size_t>(std::max(1L, std::lround(seconds / kTick)));
  s.drive.tick_s = kTick;
  s.drive.duty.assign(ticks, {});
  s.drive.anchor.assign(ticks, plant::Vec3d{});
  for (const VibrationScene& v : kVibrations)
    if (v.name == name) {
      vibration_duties(s, v.vibration, 1.0);
      return s;
    }
  if (name == "frame_edge") {
    const auto& f = s.params.frame;
    const plant::Vec3d corner =
        f.workspace_axes * plant::Vec3d{0.9 * f.workspace_half.x, 0.9 * f.workspace_half.y, 0.0};
    for (std::size_t k = 0; k < ticks; ++k) {
      const double u = std::min(1.0, static_cast<double>(k) * kTick / 0.3);
      s.drive.anchor[k] = (0.5 - 0.5 * std::cos(kPi * u)) * corner;
    }
    vibration_duties(s, kDefaultVibration, 1.0);
  } else if (name == "slack") {
    vibration_duties(s, kDefaultVibration, 1.0);
    for (std::size_t k = 0; k < ticks; ++k)
      if (k % 100 >= 60) s.drive.duty[k] = {};
  } else {  // saturation
    vibration_duties(s, kDefaultVibration, 10.0);
  }
  return s;
}

}  // namespace hmp::simulate
