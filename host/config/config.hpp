#pragma once
// The user's TOML configuration (`--config FILE.toml`): user envelope presets, the GM-program → preset
// table, mapping ranges and device settings. Unknown keys are errors naming the key, so a typo never
// silently does nothing.
//
//   [mapping]   mode = "paper"   key_scope = "song"   freq_range = [50, 250]   amp_range_db = [7.5, 30]
//   [envelope]  default = "auto"          end_fade_ms = 2             polyphony = "sum"
//   [presets.NAME]  attack_ms decay_ms release_ms (ms), sustain_pct final_pct (% of the peak)
//   [gm]        "33" = "NAME"             (program 0–127 → preset name; overrides design §6 `auto`)
//   [measured]  "33" = "NAME"             (program → preset `hmp envelope measure` fitted to its sound)
//   [device]    tick_hz = 1000            peak_force_n = 1.0 (0–20 N)   direction = [0, 1, 0] (any length:
//               the unit vector along it)
//   [plant]     the simulated plant's physics (`hmp sim`, `hmp calibrate`; checked by every command): string_stiffness
//               (N/m), string_damping (N·s/m), grip_mass (kg), motor_inertia (kg·m²), motor_inductance (H),
//               finger_stiffness (N/m), finger_damping (N·s/m), integrator = "exponential", max_step (s)
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "shared/envelope/envelope.hpp"

namespace hmp::config {

// [plant]: each value positive and finite, at most kMaxPlantValue; max_step at least kMinMaxStep.
struct PlantConfig {
  std::optional<double> string_stiffness, string_damping, grip_mass, motor_inertia, motor_inductance;
  std::optional<double> finger_stiffness, finger_damping, max_step;
  std::optional<std::string> integrator;
};
inline constexpr double kMaxPlantValue = 1e9;
// The shortest internal step: 10,000 a 1 ms tick, about 7 s of CPU a simulated second with RK4. A
// shorter one soon leaves a tick running for minutes with nothing to show (10⁻¹² s: 10⁹ steps a tick),
// and no string needs it: the bound on the ringing of 10⁹ N/m strings is ~170 kHz.
inline constexpr double kMinMaxStep = 1e-7;  // s

struct Config {
  std::optional<std::string> mapping_mode;
  std::optional<std::string> key_scope;
  std::optional<std::array<double, 2>> freq_range;
  std::optional<std::array<double, 2>> amp_range_db;
  std::optional<std::string> envelope;
  std::optional<double> end_fade_ms;
  std::optional<std::string> polyphony;
  std::map<std::string, envelope::Adsr> presets;  // user presets by (lower-case) name
  std::map<std::uint8_t, std::string> gm;         // program → preset name
  std::map<std::uint8_t, std::string> measured;   // program → preset measured from the SoundFont
  std::optional<std::uint32_t> tick_hz;
  std::optional<double> peak_force_n;
  std::optional<std::array<double, 3>> direction;
  PlantConfig plant;
};

// Throws BadInput: "FILE: unknown key 'mapping.frq_range'", "FILE:12:3: <toml parse error>", …
Config load(const std::string& path);

}  // namespace hmp::config
