// hmp — the program users type: a small, fully static front. It runs the plain forms of the light
// commands itself, `hmp info [--json] [--notes] SONG` and `hmp --version`, and execs hmp-full, the
// program with every command and the full command-line parser, for every other command line (other
// commands, help, anything unusual or wrong).
//
// Why two programs: hmp-full links the audio, plot and device libraries (FluidSynth, SDL2, cairo,
// hidapi, … about 80 shared objects), and loading them takes ~8 ms before main(), while reading a small
// song takes ~0.1 ms. The front links no shared object, and not CLI11 either: CLI11's static objects and
// the iostreams it pulls in added another 0.08 ms. Which command lines the front runs is decided below;
// for those, CLI11 in hmp-full would choose the same, so both programs print the same bytes
// (tests/cli/hmp_front.sh checks it).
#include <malloc.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstring>

#include "host/cli/info_report.hpp"
#include "host/cli/run_command.hpp"

namespace {

bool is(const char* arg, const char* word) { return std::strcmp(arg, word) == 0; }

// `info` with SONG once and each flag at most once, in any order; false → leave it to hmp-full (which
// also reports the errors: a missing SONG, an unknown option, --help, a repeated flag).
bool plain_info(int argc, char** argv, hmp::cli::InfoOptions& o) {
  if (argc < 3 || !is(argv[1], "info")) return false;
  bool have_song = false;
  for (int i = 2; i < argc; ++i) {
    const char* arg = argv[i];
    if (is(arg, hmp::cli::kInfoJsonFlag) && !o.json) {
      o.json = true;
    } else if (is(arg, hmp::cli::kInfoNotesFlag) && !o.notes) {
      o.notes = true;
    } else if (arg[0] != '-' && arg[0] != '\0' && !have_song) {
      o.song = arg;
      have_song = true;
    } else {
      return false;
    }
  }
  return have_song;
}

// hmp-full sits next to this program; /proc/self/exe names the real file even when started through a
// symbolic link or from PATH.
int exec_full(char** argv) {
  char path[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", path, sizeof path - 1);
  if (n <= 0) {
    std::fprintf(stderr, "error: cannot find hmp-full: /proc/self/exe: %s\n", std::strerror(errno));
    return hmp::cli::kExitBadInput;
  }
  path[n] = '\0';
  static constexpr char kFull[] = "hmp-full";
  const char* slash = std::strrchr(path, '/');
  const std::size_t dir_length = slash ? static_cast<std::size_t>(slash - path) + 1 : 0;
  if (dir_length + sizeof kFull > sizeof path) {
    std::fprintf(stderr, "error: cannot find hmp-full: path too long\n");
    return hmp::cli::kExitBadInput;
  }
  std::memcpy(path + dir_length, kFull, sizeof kFull);
  ::execv(path, argv);  // argv unchanged: argv[0] stays "hmp", so help and messages still say hmp
  std::fprintf(stderr, "error: cannot run %s: %s\n", path, std::strerror(errno));
  return hmp::cli::kExitBadInput;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && is(argv[1], "--version")) {
    std::printf("%s\n", hmp::cli::version_string().c_str());
    return hmp::cli::kExitOk;
  }
  hmp::cli::InfoOptions options;
  if (!plain_info(argc, argv, options)) return exec_full(argv);
  // A process this short gains nothing from giving memory back to the kernel before it exits: keep the
  // note array on the heap rather than in its own mapping (no mmap/munmap pair) and never trim the heap.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's ceiling for this setting on 64-bit
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  return hmp::cli::run_command([&options] { return hmp::cli::run_info(options); });
}
