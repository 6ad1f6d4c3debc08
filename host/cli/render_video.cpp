#include "host/cli/render_video.hpp"

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <tuple>

#include <fmt/format.h>

#include "host/cli/play_view.hpp"
#include "host/common/error.hpp"
#include "host/common/progress.hpp"
#include "host/output/output_file.hpp"
#include "host/video/video_export.hpp"

namespace hmp::cli {

std::vector<const CLI::Option*> add_video_options(CLI::App* cmd, VideoCliOptions& o) {
  const char* group = "Video (--out FILE.mp4)";
  std::vector<const CLI::Option*> video_only;
  video_only.push_back(cmd->add_option("--fps", o.fps, "Frames per second; must divide 44100 (25, 30, 50, 60 …)")
                           ->capture_default_str()
                           ->group(group));
  video_only.push_back(cmd->add_option("--size", o.size, "Frame size WIDTHxHEIGHT in pixels (even numbers)")
                           ->capture_default_str()
                           ->group(group));
  video_only.push_back(
      cmd->add_option("--zoom", o.zoom_s, "Seconds of song across the frame, as the window's + and - keys")
          ->capture_default_str()
          ->check(finite_range(1.0, 120.0))
          ->group(group));
  video_only.push_back(
      cmd->add_flag("--haptic-audio", o.haptic_audio, "A second audio stream: the haptic track's signal, listenable")
          ->group(group));
  video_only.push_back(
      cmd->add_flag("--no-audio", o.no_audio, "The song's audio stream silent (no SoundFont loaded)")->group(group));
  cmd->add_option("--soundfont", o.soundfont,
                  "SoundFont (.sf2/.sf3) for the song's sound (--sound, .mp4; default: the GM one installed)");
  video_only.push_back(cmd->add_option("--video-preset", o.preset, "libx264 speed preset: ultrafast … veryslow")
                           ->capture_default_str()
                           ->group(group));
  video_only.push_back(cmd->add_option("--crf", o.crf, "libx264 constant quality, 0..51 (lower: better and bigger)")
                           ->capture_default_str()
                           ->group(group));
  return video_only;
}

bool is_video_export(const std::string& path) { return output::extension_of(path) == "mp4"; }

namespace {

std::pair<int, int> parse_size(const std::string& text) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X')) {
    throw BadInput("--size " + text + ": expected WIDTHxHEIGHT, e.g. 1280x720");
  }
  return {w, h};
}

// The file's size, rate and encoder settings as the options give them.
video::VideoSetup encoding_of(const VideoCliOptions& o) {
  video::VideoSetup e;
  std::tie(e.width, e.height) = parse_size(o.size);
  e.fps = o.fps;
  e.preset = o.preset;
  e.crf = o.crf;
  return e;
}

}  // namespace

void check_video_options(const VideoCliOptions& o) { video::check_video_encoding(encoding_of(o)); }

void run_video_export(const std::string& song_path, const TrackWindow& w, const haptics::HapticOptions& opts,
                      const VideoCliOptions& o, const std::string& out, bool force) {
  const midi::Song& song = w.read.song;
  const midi::Track& t = song.tracks[w.track];
  video::VideoExportSpec spec;
  spec.song = &song;
  spec.haptic = std::make_shared<const haptics::HapticTrack>(w.haptic);
  spec.haptic_options = opts;
  spec.from_us = static_cast<std::int64_t>(static_cast<double>(w.first_tick) * 1e6 / opts.tick_hz + 0.5);
  spec.to_us = static_cast<std::int64_t>(static_cast<double>(w.end_tick) * 1e6 / opts.tick_hz + 0.5);
  spec.encoding = encoding_of(o);
  spec.seconds_across = o.zoom_s;
  spec.song_audio = !o.no_audio;
  spec.haptic_audio = o.haptic_audio;
  if (o.soundfont) spec.audio.soundfont = *o.soundfont;
  spec.legend_labels = legend_labels(song);
  const std::string name = std::filesystem::path(song_path).filename().string();
  spec.overlay_prefix = fmt::format("{}   track {} \"{}\"   envelope {}   mapping {}", name, w.track, t.name,
                                    opts.envelope, mapping::name(opts.mapping));
  spec.encoding.title = name;
  spec.encoding.comment = fmt::format("hmp render: track {} \"{}\", mapping {}, envelope {}", w.track, t.name,
                                      mapping::name(opts.mapping), opts.envelope);
  video::check_video_spec(spec);
  output::check_writable(out, force);
  if (out == "-") throw BadInput("--out -: a video needs a file name");

  // Ctrl-C (or a kill) stops the export cleanly: the temporary file goes, the user's file stays as it was.
  static std::atomic<bool> cancel{false};
  struct sigaction sa {};
  sa.sa_handler = [](int) { cancel.store(true); };
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
  spec.cancel = &cancel;
  ProgressBar bar("rendering video");
  const video::VideoExportResult r = video::export_video(
      out, spec, [&](std::uint64_t d, std::uint64_t n) { bar.update(d, n); }, warn_on_stderr);
  bar.update(r.frames, r.frames);
  std::fprintf(stderr, "%s: %llu frames, %.2f s of video in %.2f s (%.1fx real time): %s\n", out.c_str(),
               static_cast<unsigned long long>(r.frames), r.seconds, r.wall_s, r.seconds / r.wall_s, r.encoder.c_str());
}

}  // namespace hmp::cli
