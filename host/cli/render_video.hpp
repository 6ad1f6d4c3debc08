#pragma once
// `hmp render SONG --out FILE.mp4`: the options of the video export and its run (host/video/).
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "host/cli/song_options.hpp"

namespace hmp::cli {

struct VideoCliOptions {
  int fps = 60;
  std::string size = "1280x720";
  double zoom_s = 12.0;
  bool haptic_audio = false;
  bool no_audio = false;
  std::optional<std::string> soundfont;
  std::string preset = "ultrafast";
  int crf = 20;
};

// Returns the options that only a video takes (all but --soundfont, which --sound takes too).
std::vector<const CLI::Option*> add_video_options(CLI::App* cmd, VideoCliOptions& o);
bool is_video_export(const std::string& path);  // .mp4
// Throws BadInput for a size, rate or encoder setting that cannot work (before the output file is looked at).
void check_video_options(const VideoCliOptions& o);

// The song and track window are loaded; writes `out` (checked writable before any work).
void run_video_export(const std::string& song_path, const TrackWindow& w, const haptics::HapticOptions& opts,
                      const VideoCliOptions& o, const std::string& out, bool force);

}  // namespace hmp::cli
