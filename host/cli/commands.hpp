#pragma once
// Subcommand registration. Each subcommand file defines a register_<name>() that adds its CLI11
// subcommand and stores the action to run after parsing. cli/main.cpp registers the command named on the
// command line (every command when none is); run_cli gives it its top-level command line.
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "host/cli/run_command.hpp"

namespace hmp::cli {

inline constexpr const char* kProgramDescription =
    "hmp — Haptic Music Player: feel one instrument of a MIDI song on a SPIDAR-G6 device";

// The action chosen by the command line, run after parsing succeeded.
class Registry {
 public:
  void set(std::function<int()> action) { action_ = std::move(action); }
  int run() const;

 private:
  std::function<int()> action_;
};

// Parses the command line with the subcommands `add_commands` registers and runs the chosen one.
// A parse error is one line on stderr and exit 2 (design §3), whatever CLI11 would have chosen.
int run_cli(int argc, char** argv, void (*add_commands)(CLI::App&, Registry&));

void register_tone(CLI::App& app, Registry& registry);
void register_info(CLI::App& app, Registry& registry);
void register_render(CLI::App& app, Registry& registry);
void register_devices(CLI::App&, Registry&);
void register_play(CLI::App& app, Registry& registry);
void register_view(CLI::App& app, Registry& registry);
void register_sim(CLI::App& app, Registry& registry);
void register_study(CLI::App& app, Registry& registry);
void register_flash(CLI::App& app, Registry& registry);
void register_calibrate(CLI::App& app, Registry& registry);
void register_envelope(CLI::App& app, Registry& registry);
void register_live(CLI::App& app, Registry& registry);

// Every command, in the order help lists them (cli/main.cpp registers them; the manual describes them).
struct Command {
  const char* name;
  void (*add)(CLI::App&, Registry&);
};
inline constexpr Command kCommands[] = {
    {"info", register_info},           {"render", register_render},
    {"tone", register_tone},           {"devices", register_devices},
    {"flash", register_flash},         {"play", register_play},
    {"live", register_live},           {"sim", register_sim},
    {"study", register_study},         {"view", register_view},
    {"calibrate", register_calibrate}, {"envelope", register_envelope},
};

// The `hmp devices` lines of our HID devices found now (each greeted, `timeout_ms` for its reply); how many.
int print_hid_devices(int timeout_ms);

}  // namespace hmp::cli
