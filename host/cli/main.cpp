// hmp — the Haptic Music Player host program: every subcommand, each in its own file under host/cli/.
// The heavy back-ends (sound, plots, USB, the window) are modules it loads when a command needs them
// (host/modules/).
#include <cstring>

#include "host/cli/commands.hpp"

namespace {

// The command named first on the command line, or null (help, --version, a typo: every command is
// registered then, so top-level help and errors list them all).
const hmp::cli::Command* named_command(int argc, char** argv) {
  if (argc < 2) return nullptr;
  for (const hmp::cli::Command& c : hmp::cli::kCommands) {
    if (std::strcmp(argv[1], c.name) == 0) return &c;
  }
  return nullptr;
}

const hmp::cli::Command* g_named = nullptr;

// Only the named command is registered when there is one: building every command's options costs more
// than reading a small song (docs/host.md, "Start-up"), and CLI11 parses a command's line the same
// whether its siblings exist or not.
void register_commands(CLI::App& app, hmp::cli::Registry& registry) {
  if (g_named != nullptr) {
    g_named->add(app, registry);
    return;
  }
  for (const hmp::cli::Command& c : hmp::cli::kCommands) c.add(app, registry);
}

}  // namespace

int main(int argc, char** argv) {
  g_named = named_command(argc, argv);
  return hmp::cli::run_cli(argc, argv, register_commands);
}
