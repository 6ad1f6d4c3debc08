// bench_view_frame SONG LABEL FRAMES [--all]: the animation window's cost per frame at 1280×720 (design
// §2, benchmark view-frame). Opens the real window (the view module, vsync off) on the display in
// $DISPLAY (scripts/bench starts a private Xvfb: Mesa's llvmpipe), shows the song from a quarter of its
// length at 60 frames a song-second, and prints JSON lines: the CPU time to work out a frame (visible
// notes, layout, instances, text), the whole frame's CPU time on this thread, and the wall time to the
// end of the swap, p50 and p99. --all draws every note of the song each frame instead of the visible ones
// (what players that upload and draw all notes pay).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "host/common/percentile.hpp"
#include "host/midi/smf_reader.hpp"
#include "host/view/view_backend.hpp"
#include "tools/bench/arguments.hpp"

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: bench_view_frame SONG LABEL FRAMES [--all]\n");
    return 2;
  }
  const std::string path = argv[1], label = argv[2];
  const auto frames = static_cast<int>(hmp::bench::count_argument("FRAMES", argv[3], 1, 10000000));
  const bool all = argc > 4 && std::string(argv[4]) == "--all";
  const hmp::midi::Song song = hmp::midi::load_song(path).song;
  hmp::view::ViewSetup setup;
  setup.song = &song;
  setup.vsync = false;
  setup.draw_everything = all;
  std::string error;
  const std::unique_ptr<hmp::view::ViewWindow> window = hmp::view::open_view(setup, error);
  if (!window) {
    std::fprintf(stderr, "bench_view_frame: %s\n", error.c_str());
    return 1;
  }
  hmp::view::FrameState state;
  state.end_us = std::llround(song.duration_s() * 1e6);
  state.overlay = "playing";
  for (std::uint32_t t = 0; t < song.tracks.size(); ++t)
    state.legend.push_back({t, "track " + std::to_string(t), t == 0, false});
  std::vector<hmp::view::ViewEvent> events;
  std::vector<double> prepare, cpu, wall;
  std::size_t instances = 0;
  const std::int64_t start_us = state.end_us / 4;
  for (int i = -30; i < frames; ++i) {  // 30 frames to warm up
    state.song_us = start_us + std::llround((i + 30) * 1e6 / 60.0);
    // The overlay's clock changes ten times a second, as in `hmp play`.
    state.overlay = "playing " + std::to_string(state.song_us / 100'000);
    if (!window->frame(state, events)) return 1;
    if (i < 0) continue;
    const hmp::view::FrameCost c = window->last_cost();
    prepare.push_back(c.prepare_cpu_ms);
    cpu.push_back(c.frame_cpu_ms);
    wall.push_back(c.wall_ms);
    instances = std::max(instances, c.instances);
  }
  const std::string params =
      "{\"song\":\"" + label + "\",\"notes\":" + std::to_string(song.notes.size()) + ",\"mode\":\"" +
      (all ? "all-notes" : "visible") + "\",\"size\":\"1280x720\",\"frames\":" + std::to_string(frames) +
      ",\"max_instances\":" + std::to_string(instances) + ",\"renderer\":\"" + window->renderer() + "\"}";
  auto line = [&](const char* metric, double value) {
    std::printf("{\"bench\":\"view-frame\",\"metric\":\"%s\",\"value\":%.3f,\"unit\":\"ms\",\"params\":%s}\n", metric,
                value, params.c_str());
  };
  line("prepare_cpu_p50", hmp::percentile(prepare, 50));
  line("prepare_cpu_p99", hmp::percentile(prepare, 99));
  line("frame_cpu_p50", hmp::percentile(cpu, 50));
  line("frame_cpu_p99", hmp::percentile(cpu, 99));
  line("frame_wall_p50", hmp::percentile(wall, 50));
  line("frame_wall_p99", hmp::percentile(wall, 99));
  return 0;
}
