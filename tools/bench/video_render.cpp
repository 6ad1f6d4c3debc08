// video-render (docs/exports.md): how fast `hmp render --out FILE.mp4` makes a video, as a
// multiple of real time, through the same library call the command makes (host/video/video_export.hpp):
// the demo song's flute over a passage, frames drawn off-screen by Mesa's llvmpipe (no GPU), H.264 by
// libx264, the song's sound by FluidSynth. Prints JSON lines: real-time factor, frames per second, and
// where the wall time went (audio rendered first; drawing and encoding overlap on two threads).
//
// Usage: bench_video_render SONG TRACK SECONDS PRESET WIDTHxHEIGHT FPS OUT.mp4
#include <cstdio>
#include <cstdlib>
#include <string>

#include <fmt/format.h>

#include "host/haptics/track_window.hpp"
#include "host/video/video_export.hpp"
#include "tools/bench/arguments.hpp"

int main(int argc, char** argv) {
  if (argc != 8) {
    std::fprintf(stderr, "usage: %s SONG TRACK SECONDS PRESET WIDTHxHEIGHT FPS OUT.mp4\n", argv[0]);
    return 2;
  }
  const std::string song_path = argv[1], track = argv[2], preset = argv[4], size = argv[5], out = argv[7];
  const double seconds = hmp::bench::number_argument("SECONDS", argv[3], 0.001, 86400);
  const auto fps = static_cast<int>(hmp::bench::count_argument("FPS", argv[6], 1, 1000));
  int width = 0, height = 0;
  if (std::sscanf(size.c_str(), "%dx%d", &width, &height) != 2) return 2;
  try {
    hmp::haptics::HapticOptions opts;
    const auto w =
        hmp::haptics::load_track_window(song_path, track, opts, 30.0, 30.0 + seconds, [](const std::string&) {});
    hmp::video::VideoExportSpec spec;
    spec.song = &w.read.song;
    spec.haptic = std::make_shared<const hmp::haptics::HapticTrack>(w.haptic);
    spec.haptic_options = opts;
    spec.from_us = 30'000'000;
    spec.to_us = spec.from_us + static_cast<std::int64_t>(seconds * 1e6);
    spec.encoding.width = width;
    spec.encoding.height = height;
    spec.encoding.fps = fps;
    spec.encoding.preset = preset;
    spec.overlay_prefix = "bench";
    const hmp::video::VideoExportResult r = hmp::video::export_video(
        out, spec, {}, [](const std::string& m) { std::fprintf(stderr, "warning: %s\n", m.c_str()); });
    const std::string params = fmt::format(
        R"({{"song":"{}","track":"{}","seconds":{},"preset":"{}","size":"{}","fps":{},)"
        R"("renderer":"{}","encoder":"{}"}})",
        song_path.substr(song_path.find_last_of('/') + 1), track, seconds, preset, size, fps, r.renderer, r.encoder);
    auto line = [&](const char* metric, double value, const char* unit) {
      std::printf(R"({"bench":"video-render","metric":"%s","value":%.3f,"unit":"%s","params":%s})"
                  "\n",
                  metric, value, unit, params.c_str());
    };
    line("realtime_factor", r.seconds / r.wall_s, "x");
    line("frames_per_s", static_cast<double>(r.frames) / r.wall_s, "frames/s");
    line("audio_s", r.audio_wall_s, "s");
    line("draw_s", r.render_wall_s, "s");
    line("encode_s", r.encode_wall_s, "s");
    line("wall_s", r.wall_s, "s");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
