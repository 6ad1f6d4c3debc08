#pragma once
// host/video/: `hmp render SONG --out FILE.mp4` — the animation of the window rendered off-screen at a
// fixed frame rate, with the song's sound from FluidSynth and, optionally, the haptic track's signal as a
// second audio stream, encoded into one MP4 file (docs/exports.md). Frame i shows song time
// from + i/fps and carries audio samples [i·s, (i+1)·s) with s = sample_rate / fps (735 at 44.1 kHz and
// 60 fps): picture and sound are locked sample for sample, whatever the machine's speed.
//
// The frames come from the view module's off-screen painter (the window's own), the audio from the
// audio module's offline renderer, the encoding from the video module (host/video/av/).
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "host/audio/audio_events.hpp"
#include "host/audio/audio_options.hpp"
#include "host/haptics/haptic_track.hpp"
#include "host/haptics/signal_tail.hpp"
#include "host/midi/song.hpp"
#include "host/video/video_backend.hpp"
#include "host/view/view_backend.hpp"

namespace hmp::video {

struct VideoExportSpec {
  const midi::Song* song = nullptr;
  std::shared_ptr<const haptics::HapticTrack> haptic;  // the haptic track (front layer, strip, 2nd audio)
  haptics::HapticOptions haptic_options;
  std::int64_t from_us = 0, to_us = 0;  // the passage, song time
  // The file's size, rate, encoder settings and metadata; its path and audio streams are the export's.
  VideoSetup encoding;
  double seconds_across = 12.0;               // the roll's zoom, as in the window
  audio::AudioOptions audio;                  // the SoundFont
  bool song_audio = true;                     // false: a silent song stream (--no-audio)
  bool haptic_audio = false;                  // a second stream: the haptic signal, listenable
  std::vector<std::string> legend_labels;     // per track, "" = not listed (as the window)
  std::string overlay_prefix;                 // the top line before the clock (song, track, options)
  const std::atomic<bool>* cancel = nullptr;  // set (e.g. by Ctrl-C): stop, write nothing
};

struct VideoExportResult {
  std::uint64_t frames = 0;
  std::uint64_t samples_per_frame = 0;
  double seconds = 0;        // of video
  double wall_s = 0;         // how long the export took
  double render_wall_s = 0;  // of which drawing and reading back frames
  double encode_wall_s = 0;  // of which converting, encoding and writing (on its own thread, overlapped)
  double audio_wall_s = 0;   // of which rendering the audio (FluidSynth, before the frames)
  std::string encoder;       // the video module's summary
  std::string renderer;      // the GL renderer
};

using Progress = std::function<void(std::uint64_t done, std::uint64_t total)>;

// Throws BadInput for options that cannot work (fps not dividing the sample rate, odd sizes, …) before
// any work, and std::runtime_error (one line: what and why) when a module is missing or encoding fails.
// Writes `path` through a temporary file beside it: nothing is left behind on failure or cancel (which
// throws std::runtime_error "interrupted").
VideoExportResult export_video(const std::string& path, const VideoExportSpec& spec, const Progress& progress,
                               const audio::WarningSink& warn);

// The checks of export_video that need no work (the command calls it before loading modules).
void check_video_spec(const VideoExportSpec& spec);
// The part of them on the file's size, rate and encoder settings alone (a command checks its options with
// it before it looks at the output file or reads the song).
void check_video_encoding(const VideoSetup& encoding);

// What the frame at `song_us` shows (overlay, legend, strip; the bars come from the song): the state the
// off-screen painter draws. `tail` is the haptic track's (SignalTail(spec.haptic, spec.haptic_options)).
view::FrameState video_frame_state(const VideoExportSpec& spec, const haptics::SignalTail& tail, std::int64_t song_us);

// Song time shown by frame `i` of a video starting at `from_us`: from + i/fps, rounded to the µs.
std::int64_t frame_time_us(std::int64_t from_us, std::uint64_t i, int fps);
// How many frames cover [from_us, to_us): at least one.
std::uint64_t frame_count(std::int64_t from_us, std::int64_t to_us, int fps);

}  // namespace hmp::video
