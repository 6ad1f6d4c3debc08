// hmp info SONG [--json [--notes]]: the command line of `info`; the work is in info_report.cpp.
#include <memory>

#include "host/cli/commands.hpp"
#include "host/cli/info_report.hpp"

namespace hmp::cli {

void register_info(CLI::App& app, Registry& registry) {
  auto o = std::make_shared<InfoOptions>();
  CLI::App* cmd = app.add_subcommand("info", "Show a song's tracks, instruments, key ranges, tempo and warnings");
  cmd->add_option("SONG", o->song, "MIDI file (.mid, RMID)")->required();
  CLI::Option* json = cmd->add_flag(kInfoJsonFlag, o->json, "Print one JSON object");
  cmd->add_flag(kInfoNotesFlag, o->notes, "With --json: include every note of every track")->needs(json);
  add_haptic_options(cmd, o->haptic);
  cmd->callback([o, &registry] { registry.set([o] { return run_info(*o); }); });
}

}  // namespace hmp::cli
