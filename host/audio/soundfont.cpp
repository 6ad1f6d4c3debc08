#include "host/audio/soundfont.hpp"

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>

namespace hmp::audio {

namespace {
bool readable_file(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec) && ::access(path.c_str(), R_OK) == 0;
}
}  // namespace

const std::vector<std::string>& standard_soundfont_paths() {
  static const std::vector<std::string> paths = {
      "/usr/share/sounds/sf2/FluidR3_GM.sf2",    // fluid-soundfont-gm (Debian, Ubuntu)
      "/usr/share/sounds/sf2/default-GM.sf2",    // Debian's alternatives link
      "/usr/share/soundfonts/FluidR3_GM.sf2",    // Fedora, Arch
      "/usr/share/soundfonts/default.sf2",       // Arch's default link
      "/usr/share/sounds/sf3/default-GM.sf3",    // Debian's compressed-SoundFont alternative
  };
  return paths;
}

std::optional<std::string> find_soundfont(const std::string& explicit_path) {
  if (!explicit_path.empty()) {
    if (readable_file(explicit_path)) return explicit_path;
    return std::nullopt;
  }
  for (const std::string& p : standard_soundfont_paths()) {
    if (readable_file(p)) return p;
  }
  return std::nullopt;
}

std::string soundfont_format_problem(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "cannot read it";
  char head[12] = {};
  in.read(head, sizeof(head));
  if (in.gcount() != static_cast<std::streamsize>(sizeof(head)) || std::memcmp(head, "RIFF", 4) != 0 ||
      std::memcmp(head + 8, "sfbk", 4) != 0) {
    return "not a SoundFont 2 file";
  }
  return "";
}

}  // namespace hmp::audio
