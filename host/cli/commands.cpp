#include "host/cli/commands.hpp"

#include <cstdio>

namespace hmp::cli {

int Registry::run() const { return action_ ? run_command(action_) : kExitBadInput; }

int run_cli(int argc, char** argv, void (*add_commands)(CLI::App&, Registry&)) {
  CLI::App app{kProgramDescription};
  app.require_subcommand(1);
  app.set_version_flag("--version", version_string());
  Registry registry;
  add_commands(app, registry);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "error: %s (try --help)\n", e.what());
    return kExitBadInput;
  }
  return registry.run();
}

}  // namespace hmp::cli
