#pragma once
// Subcommand registration. Each subcommand file defines a register_<name>() that adds its CLI11
// subcommand and stores the action to run after parsing.
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

namespace hmp::cli {

// Exit codes (SPEC §3).
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;   // a run that failed for a reason other than bad input
inline constexpr int kExitBadInput = 2;  // bad file, bad option: one-line message on stderr

// The action chosen by the command line, run after parsing succeeded.
class Registry {
 public:
  void set(std::function<int()> action) { action_ = std::move(action); }
  int run() const;
 private:
  std::function<int()> action_;
};

std::string version_string();
void register_all(CLI::App& app, Registry& registry);

void register_tone(CLI::App& app, Registry& registry);
void register_info(CLI::App& app, Registry& registry);
void register_render(CLI::App& app, Registry& registry);
void register_devices(CLI::App&, Registry&);
void register_play(CLI::App& app, Registry& registry);
void register_sim(CLI::App& app, Registry& registry);

}  // namespace hmp::cli
