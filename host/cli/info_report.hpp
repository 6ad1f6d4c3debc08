#pragma once
// `hmp info`'s work, apart from its command line (info_command.cpp): load a song and print what is in it
// (design §3).
#include <string>

#include "host/cli/song_options.hpp"

namespace hmp::cli {

// The flags of `hmp info`, spelled once for the CLI11 registration and for the front's recogniser.
inline constexpr const char* kInfoJsonFlag = "--json";
inline constexpr const char* kInfoNotesFlag = "--notes";

struct InfoOptions {
  std::string song;
  bool json = false;
  bool notes = false;       // with json: every note of every track
  HapticCliOptions haptic;  // the mapping whose frequencies the table shows, the config's GM table
};

// Prints the song's summary (a table, or one JSON object) on stdout; returns kExitOk. Throws BadInput
// for a file it cannot read.
int run_info(const InfoOptions& options);

}  // namespace hmp::cli
