#include "host/audio/soundfont.hpp"

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>

namespace hmp::audio {

namespace {
bool readable_file(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec) && ::access(path.c_str(), R_OK) == 0;
}
}  // namespace

const std::vector<std::string>& standard_soundfont_paths() {
  static const std::vector<std::string> paths = {
      "/usr/share/sounds/sf2/FluidR3_GM.sf2",  // fluid-soundfont-gm (Debian, Ubuntu)
      "/usr/share/sounds/sf2/default-GM.sf2",  // Debian's alternatives link
      "/usr/share/soundfonts/FluidR3_GM.sf2",  // Fedora, Arch
      "/usr/share/soundfonts/default.sf2",     // Arch's default link
      "/usr/share/sounds/sf3/default-GM.sf3",  // Debian's compressed-SoundFont alternative
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

std::set<std::uint8_t> soundfont_programs(const std::string& path, std::uint16_t bank) {
  std::set<std::uint8_t> out;
  std::ifstream in(path, std::ios::binary);
  const auto u32 = [](const unsigned char* b) {
    return static_cast<std::uint32_t>(b[0] | b[1] << 8 | b[2] << 16 | static_cast<std::uint32_t>(b[3]) << 24);
  };
  // RIFF 'sfbk' holds LIST chunks; the 'pdta' list's 'phdr' chunk has one 38-byte record per preset
  // (name[20], preset, bank, …), the last one the terminal "EOP".
  unsigned char head[12];
  if (!in.read(reinterpret_cast<char*>(head), 12) || std::memcmp(head + 8, "sfbk", 4) != 0) return out;
  unsigned char ck[12];
  while (in.read(reinterpret_cast<char*>(ck), 8)) {
    const std::uint32_t size = u32(ck + 4);
    if (std::memcmp(ck, "LIST", 4) != 0) {
      in.seekg(size + (size & 1u), std::ios::cur);
      continue;
    }
    if (!in.read(reinterpret_cast<char*>(ck + 8), 4)) break;
    if (std::memcmp(ck + 8, "pdta", 4) != 0) {
      in.seekg(size - 4 + (size & 1u), std::ios::cur);
      continue;
    }
    for (std::uint32_t done = 4; done + 8 <= size;) {
      if (!in.read(reinterpret_cast<char*>(ck), 8)) return out;
      const std::uint32_t sub = u32(ck + 4);
      if (std::memcmp(ck, "phdr", 4) == 0) {
        unsigned char rec[38];
        for (std::uint32_t r = 0; r + 1 < sub / 38; ++r) {  // the terminal record is not a preset
          if (!in.read(reinterpret_cast<char*>(rec), 38)) return out;
          const unsigned preset = rec[20] | rec[21] << 8, preset_bank = rec[22] | rec[23] << 8;
          if (preset_bank == bank && preset < 128) out.insert(static_cast<std::uint8_t>(preset));
        }
        return out;
      }
      in.seekg(sub + (sub & 1u), std::ios::cur);
      done += 8 + sub + (sub & 1u);
    }
    return out;
  }
  return out;
}

}  // namespace hmp::audio
