// hmp-full — the whole Haptic Music Player host program: every subcommand, each in its own file under
// host/cli/. Users type `hmp`, the small static front (front_main.cpp) that runs `info` itself and
// hands everything else to this program.
#include "host/cli/commands.hpp"

namespace {

void register_all(CLI::App& app, hmp::cli::Registry& registry) {
  hmp::cli::register_info(app, registry);
  hmp::cli::register_render(app, registry);
  hmp::cli::register_tone(app, registry);
  hmp::cli::register_devices(app, registry);
  hmp::cli::register_flash(app, registry);
  hmp::cli::register_play(app, registry);
  hmp::cli::register_sim(app, registry);
  hmp::cli::register_study(app, registry);
}

}  // namespace

int main(int argc, char** argv) { return hmp::cli::run_cli(argc, argv, register_all); }
