// midi-parse, in-process part (design §4): hmp's reader timed the way mido is timed (tools/bench/
// mido_pairing.py), inside a running process, so that neither side's start-up is counted. Times
// midi::load_song (read the file, parse, pair the notes, tempo map, programs, per-track statistics) with
// a steady clock around the call.
//
// Usage: bench_midi_parse_inprocess [--repeat N] FILE
// Prints one JSON object: {"first_seconds": the first load in this process (cold, as mido's single parse
// in a fresh interpreter), "best_seconds": the best of N loads (warm: the allocator reuses the pages of
// the previous load), "notes": paired notes, "repeat": N}. The driver (midi_parse.py) runs it once per
// round, taking turns with the other tools.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>

#include "host/midi/smf_reader.hpp"
#include "tools/bench/arguments.hpp"

namespace {

struct Load {
  double seconds = 0;
  std::size_t notes = 0;
};

Load timed_load(const char* path) {
  const auto start = std::chrono::steady_clock::now();
  const hmp::midi::ReadResult r = hmp::midi::load_song(path);
  const auto stop = std::chrono::steady_clock::now();
  // The song is destroyed after the clock stops: freeing is not part of mido's figure either.
  return Load{std::chrono::duration<double>(stop - start).count(), r.song.notes.size()};
}

}  // namespace

int main(int argc, char** argv) {
  int repeat = 1;
  const char* path = nullptr;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--repeat") == 0 && i + 1 < argc) {
      repeat = static_cast<int>(hmp::bench::count_argument("--repeat", argv[++i], 1, 1000000));
    } else if (path == nullptr && argv[i][0] != '-') {
      path = argv[i];
    } else {
      path = nullptr;
      break;
    }
  }
  if (path == nullptr) {
    std::fprintf(stderr, "usage: %s [--repeat N] FILE\n", argv[0]);
    return 2;
  }
  try {
    const Load first = timed_load(path);
    double best = first.seconds;
    for (int i = 1; i < repeat; ++i) best = std::min(best, timed_load(path).seconds);
    std::printf("{\"first_seconds\":%.9f,\"best_seconds\":%.9f,\"notes\":%zu,\"repeat\":%d}\n", first.seconds, best,
                first.notes, repeat);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_midi_parse_inprocess: %s\n", e.what());
    return 1;
  }
  return 0;
}
