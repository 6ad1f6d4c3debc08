// hmp — the Haptic Music Player host program. Each subcommand lives in its own file under host/cli/
// and registers itself here.
#include <cstdio>

#include <CLI/CLI.hpp>

#include "host/cli/commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"hmp — Haptic Music Player: feel one instrument of a MIDI song on a SPIDAR-G6 device"};
  app.require_subcommand(1);
  app.set_version_flag("--version", hmp::cli::version_string());
  hmp::cli::Registry registry;
  hmp::cli::register_all(app, registry);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // One line, exit 2 (SPEC §3), whatever CLI11 would have chosen.
    std::fprintf(stderr, "error: %s (try --help)\n", e.what());
    return 2;
  }
  return registry.run();
}
