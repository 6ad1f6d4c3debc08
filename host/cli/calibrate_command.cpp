// hmp calibrate — the 1 mm set-up of the 2015 paper (§6.1): the force of full scale (the config's
// [device] peak_force_n) set so that a full-scale sine moves the grip the target peak displacement.
// Measured on the simulated device's plant (host/simulate/calibration.hpp says why not on hardware).
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "host/cli/commands.hpp"
#include "host/common/error.hpp"
#include "host/common/input_file.hpp"
#include "host/config/config.hpp"
#include "host/output/output_file.hpp"
#include "host/config/config_edit.hpp"
#include "host/haptics/haptic_track.hpp"
#include "host/simulate/calibration.hpp"
#include "host/simulate/plant_config.hpp"
#include "host/transport/device_spec.hpp"

namespace hmp::cli {

namespace {

constexpr double kDefaultHz = 100.0;
constexpr double kMaxTargetMm = 20.0;  // more than the grip's travel in a vibration; a typo

struct CalibrateOptions {
  double target_mm = 1.0;
  std::optional<double> frequency_hz;
  std::string device = "sim";
  std::optional<std::string> config_path;
  bool force = false;
};

void check_options(const CalibrateOptions& o) {
  if (!std::isfinite(o.target_mm) || o.target_mm <= 0 || o.target_mm > kMaxTargetMm) {
    throw BadInput(fmt::format("--target-mm: must be in (0, {:g}] mm", kMaxTargetMm));
  }
  if (o.frequency_hz && !(*o.frequency_hz >= simulate::kBandLowHz && *o.frequency_hz <= simulate::kBandHighHz)) {
    throw BadInput(
        fmt::format("--frequency: must be in the band {:g}–{:g} Hz", simulate::kBandLowHz, simulate::kBandHighHz));
  }
  if (transport::parse_device_spec(o.device).kind != transport::DeviceSpec::Kind::sim) {
    throw BadInput("--device " + o.device +
                   ": only sim can be measured (a device reports its grip 100 times a "
                   "second, too slowly for a 50–250 Hz vibration)");
  }
}

// The setup the player would use: the config's direction and tick rate, and its [plant] (the device the
// user simulates; hmp sim takes the same).
simulate::CalibrationSetup setup_from(const config::Config& cfg) {
  simulate::CalibrationSetup s;
  if (cfg.tick_hz) s.tick_hz = *cfg.tick_hz;
  if (cfg.direction) s.direction = *cfg.direction;
  simulate::apply_plant_settings(cfg.plant, {}, s.plant);
  return s;
}

void print_reach(const std::vector<simulate::GripMotion>& band) {
  std::printf("largest peak displacement per frequency (simulated plant):\n");
  for (const simulate::GripMotion& g : band) {
    std::printf("  %3.0f Hz  %6.3f mm  at peak_force_n %5.2f N\n", g.hz, g.displacement_m * 1e3, g.peak_force_n);
  }
}

// The found force across the band, next to the most each frequency allows. Where that force is more
// than a frequency allows, a full-scale note there stops the device (its strings go slack).
void report_band(const simulate::CalibrationSetup& setup, double newtons) {
  std::printf("across the band: at %.5g N            largest reachable\n", newtons);
  for (const simulate::GripMotion& top : simulate::reach_band(setup)) {
    const simulate::GripMotion at = simulate::measure_grip(setup, top.hz, newtons);
    const std::string here = at.faults ? "device fault" : fmt::format("{:6.3f} mm", at.displacement_m * 1e3);
    std::printf("  %3.0f Hz  %-12s          %6.3f mm at %5.2f N\n", top.hz, here.c_str(), top.displacement_m * 1e3,
                top.peak_force_n);
    if (at.faults) {
      std::fprintf(stderr, "warning: at %.5g N a full-scale %g Hz vibration faults the device (at most %.2f N)\n",
                   newtons, top.hz, top.peak_force_n);
    }
  }
}

void write_config(const std::string& path, bool exists, double newtons) {
  const std::string old = exists ? read_input_file(path) : std::string{};
  const std::string text = config::with_peak_force(old, newtons);
  output::FilePtr f = output::open_for_writing(path, true);  // asked (or --force) before this
  if (std::fwrite(text.data(), 1, text.size(), f.get()) != text.size() || std::fflush(f.get()) != 0) {
    throw std::runtime_error(path + ": write failed");
  }
  // The edited file must read back with the new value before it replaces the old one.
  config::Config back;
  try {
    back = config::load(output::part_path(path));
  } catch (const BadInput& e) {  // our edit's fault, not the user's file: the file stays as it was
    throw std::runtime_error(path + ": the edited config would not read back, so it is left as it was (" + e.what() +
                             ")");
  }
  if (!back.peak_force_n || std::fabs(*back.peak_force_n - newtons) > 1e-3 * newtons) {
    throw std::runtime_error(path + ": the edited config does not read back peak_force_n");
  }
  output::close_output(f);
}

int run_calibrate(const CalibrateOptions& o) {
  check_options(o);
  const double target_m = o.target_mm * 1e-3, hz = o.frequency_hz.value_or(kDefaultHz);
  namespace fs = std::filesystem;
  std::error_code ec;
  const bool exists = o.config_path && fs::exists(*o.config_path, ec);
  const config::Config cfg = exists ? config::load(*o.config_path) : config::Config{};
  // Before any work: a folder that is not there, or a file that may not be replaced without asking
  // when nobody can be asked.
  const bool can_ask = isatty(STDIN_FILENO) && isatty(STDERR_FILENO);
  if (o.config_path) output::check_writable(*o.config_path, o.force || can_ask);
  const simulate::CalibrationSetup setup = setup_from(cfg);
  if (simulate::kBandHighHz >= haptics::kHighestFreqFraction * setup.tick_hz) {
    throw BadInput(fmt::format("{}: [device] tick_hz {}: the band's {:g} Hz is above {:g} × the tick rate (aliasing)",
                               o.config_path.value_or("config"), setup.tick_hz, simulate::kBandHighHz,
                               haptics::kHighestFreqFraction));
  }

  std::printf("reference: %g Hz sine at full scale on the simulated plant, target %g mm peak\n", hz, o.target_mm);
  const simulate::Calibration c = simulate::calibrate(setup, hz, target_m);
  for (const simulate::GripMotion& g : c.steps) {
    std::printf("  peak_force_n %6.3f N -> %6.3f mm%s\n", g.peak_force_n, g.displacement_m * 1e3,
                g.faults ? " (device fault: too much)" : "");
  }
  if (c.out_of_reach()) {
    print_reach(simulate::reach_band(setup));
    throw BadInput(fmt::format("{:g} mm at {:g} Hz is out of reach: at most {:.3f} mm (peak_force_n {:.2f} N)",
                               o.target_mm, hz, c.limit->displacement_m * 1e3, c.limit->peak_force_n));
  }
  if (!c.reached) throw std::runtime_error("the measurement did not settle on a force (not linear here)");
  if (!o.frequency_hz) report_band(setup, c.peak_force_n);
  const std::string was = cfg.peak_force_n ? fmt::format("{:g} N", *cfg.peak_force_n) : "unset (1 N)";
  std::printf("[device] peak_force_n: %s -> %.5g N\n", was.c_str(), c.peak_force_n);
  if (!o.config_path) {
    std::printf("not saved: give --config FILE to write it\n");
    return kExitOk;
  }
  std::fflush(stdout);
  output::check_writable(*o.config_path, o.force);  // asks on a terminal, after the values are shown
  write_config(*o.config_path, exists, c.peak_force_n);
  std::printf("saved to %s\n", o.config_path->c_str());
  return kExitOk;
}

}  // namespace

void register_calibrate(CLI::App& app, Registry& registry) {
  auto o = std::make_shared<CalibrateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate", "The 1 mm set-up: find the peak force at which a full-scale sine moves the grip --target-mm");
  cmd->add_option("--target-mm", o->target_mm, "Peak displacement of the grip in mm")->capture_default_str();
  cmd->add_option("--frequency", o->frequency_hz,
                  "Reference sine in Hz (50–250; default 100, and the whole band is reported)");
  cmd->add_option("--device", o->device, "Device to measure on (only sim: the simulated plant)")->capture_default_str();
  cmd->add_option("--config", o->config_path, "Config file whose [device] peak_force_n is set (created if absent)");
  cmd->add_flag("-f,--force", o->force, "Replace the config file without asking");
  cmd->callback([o, &registry] { registry.set([o] { return run_calibrate(*o); }); });
}

}  // namespace hmp::cli
