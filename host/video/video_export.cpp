#include "host/video/video_export.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <mutex>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>

#include "host/audio/offline_render.hpp"
#include "host/common/error.hpp"
#include "host/common/time_format.hpp"
#include "host/haptics/signal_renderer.hpp"
#include "host/haptics/signal_tail.hpp"
#include "host/modules/module_loader.hpp"
#include "host/output/output_file.hpp"
#include "host/audio/wav_file.hpp"
#include "host/video/video_backend.hpp"
#include "host/video/yuv_convert.hpp"
#include "host/view/view_backend.hpp"

namespace hmp::video {
namespace {

using WallClock = std::chrono::steady_clock;

double seconds_since(WallClock::time_point t0) { return std::chrono::duration<double>(WallClock::now() - t0).count(); }

// Exactly `n` samples: the renderers round the passage's ends to their own grids.
void fit(std::vector<float>& v, std::size_t n) { v.resize(n, 0.0f); }

// Frames on their way from the drawing thread to the encoding thread: a few buffers handed back and forth,
// so drawing (and converting) frame i+1 overlaps encoding frame i.
class FrameQueue {
 public:
  FrameQueue(std::size_t buffers, std::size_t bytes) {
    for (std::size_t i = 0; i < buffers; ++i) free_.push_back(std::vector<std::uint8_t>(bytes));
  }
  std::vector<std::uint8_t> take_free() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return !free_.empty() || aborted_; });
    if (aborted_) return {};
    auto b = std::move(free_.front());
    free_.pop_front();
    return b;
  }
  void put_full(std::vector<std::uint8_t> b) {
    std::lock_guard lock(mutex_);
    full_.push_back(std::move(b));
    changed_.notify_all();
  }
  // Empty at the end (after close()) or after abort().
  std::vector<std::uint8_t> take_full() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return !full_.empty() || closed_ || aborted_; });
    if (aborted_ || full_.empty()) return {};
    auto b = std::move(full_.front());
    full_.pop_front();
    return b;
  }
  void put_free(std::vector<std::uint8_t> b) {
    std::lock_guard lock(mutex_);
    free_.push_back(std::move(b));
    changed_.notify_all();
  }
  void close() {
    std::lock_guard lock(mutex_);
    closed_ = true;
    changed_.notify_all();
  }
  void abort() {
    std::lock_guard lock(mutex_);
    aborted_ = true;
    changed_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::vector<std::uint8_t>> free_, full_;
  bool closed_ = false, aborted_ = false;
};

}  // namespace

view::FrameState video_frame_state(const VideoExportSpec& spec, const haptics::SignalTail& tail, std::int64_t song_us) {
  view::FrameState f;
  f.song_us = song_us;
  f.end_us = spec.to_us;
  f.haptic_track = spec.haptic->track;
  f.previous_haptic = spec.haptic->track;
  f.depth_blend = 1.0f;
  f.seconds_across = spec.seconds_across;
  f.overlay = fmt::format("{}  {} / {}", spec.overlay_prefix, format_time(song_us), format_time(spec.to_us));
  for (std::size_t t = 0; t < spec.legend_labels.size(); ++t) {
    if (spec.legend_labels[t].empty()) continue;
    const auto track = static_cast<std::uint32_t>(t);
    f.legend.push_back({track, spec.legend_labels[t], track == spec.haptic->track, false});
  }
  f.vibration_samples = tail.samples(song_us, f.vibration, 256);
  return f;
}

std::int64_t frame_time_us(std::int64_t from_us, std::uint64_t i, int fps) {
  const auto f = static_cast<std::uint64_t>(fps);
  return from_us + static_cast<std::int64_t>((i * 1'000'000 + f / 2) / f);
}

std::uint64_t frame_count(std::int64_t from_us, std::int64_t to_us, int fps) {
  if (to_us <= from_us) return 1;
  const auto span = static_cast<std::uint64_t>(to_us - from_us);
  const auto f = static_cast<std::uint64_t>(fps);
  return std::max<std::uint64_t>(1, (span * f + 999'999) / 1'000'000);
}

void check_video_encoding(const VideoSetup& encoding) {
  if (encoding.fps < 1 || encoding.fps > 240) throw BadInput(fmt::format("--fps {}: out of 1..240", encoding.fps));
  if (encoding.sample_rate % encoding.fps != 0) {
    throw BadInput(
        fmt::format("--fps {}: {} Hz audio does not divide into whole samples per frame (try 25, 30, 50 or 60)",
                    encoding.fps, encoding.sample_rate));
  }
  if (encoding.width < 16 || encoding.height < 16 || encoding.width > 7680 || encoding.height > 4320 ||
      encoding.width % 2 != 0 || encoding.height % 2 != 0) {
    throw BadInput(fmt::format("--size {}x{}: from 16x16 to 7680x4320, both even", encoding.width, encoding.height));
  }
  if (encoding.crf < 0 || encoding.crf > 51) throw BadInput(fmt::format("--crf {}: out of 0..51", encoding.crf));
  static const char* const kPresets[] = {"ultrafast", "superfast", "veryfast", "faster",  "fast",
                                         "medium",    "slow",      "slower",   "veryslow"};
  if (std::find(std::begin(kPresets), std::end(kPresets), encoding.preset) == std::end(kPresets)) {
    throw BadInput("--video-preset " + encoding.preset +
                   ": one of ultrafast, superfast, veryfast, faster, fast, medium, slow, slower, veryslow");
  }
}

void check_video_spec(const VideoExportSpec& spec) {
  check_video_encoding(spec.encoding);
  if (spec.song == nullptr || !spec.haptic) throw BadInput("video export: no song");
  if (spec.to_us <= spec.from_us) throw BadInput("video export: empty passage");
}

VideoExportResult export_video(const std::string& path, const VideoExportSpec& spec, const Progress& progress,
                               const audio::WarningSink& warn) {
  check_video_spec(spec);
  const auto started = WallClock::now();
  VideoExportResult result;
  result.frames = frame_count(spec.from_us, spec.to_us, spec.encoding.fps);
  result.samples_per_frame = static_cast<std::uint64_t>(spec.encoding.sample_rate / spec.encoding.fps);
  result.seconds = static_cast<double>(result.frames) / spec.encoding.fps;
  const std::size_t samples = result.frames * result.samples_per_frame;
  const std::int64_t audio_end_us = frame_time_us(spec.from_us, result.frames, spec.encoding.fps) + 1;

  // The modules first: a missing one is reported before minutes of audio rendering.
  std::string why;
  const VideoBackend* backend = modules::backend<VideoBackend>(&why);
  if (backend == nullptr)
    throw std::runtime_error("cannot write " + path + ": the video module is not available (" + why + ")");
  view::ViewSetup view_setup;
  view_setup.song = spec.song;
  view_setup.width = spec.encoding.width;
  view_setup.height = spec.encoding.height;
  std::unique_ptr<view::OffscreenFrames> frames = view::open_offscreen(view_setup, why);
  if (!frames) throw std::runtime_error("cannot draw the video's frames: " + why);
  result.renderer = frames->renderer();

  // The sound, all of it first (FluidSynth runs far faster than real time).
  const auto audio_started = WallClock::now();
  std::vector<std::vector<float>> streams;  // per audio stream, its channels one after the other
  std::vector<int> channels;
  {
    audio::RenderedAudio song_audio;
    if (spec.song_audio) {
      audio::AudioOptions options = spec.audio;
      options.synth.sample_rate = spec.encoding.sample_rate;
      song_audio = audio::render_offline(audio::audio_events(*spec.song), spec.from_us, audio_end_us, options, warn);
    }
    fit(song_audio.left, samples);
    fit(song_audio.right, samples);
    streams.push_back(std::move(song_audio.left));
    streams.push_back(std::move(song_audio.right));
    channels.push_back(2);
  }
  if (spec.haptic_audio) {
    const std::uint32_t tick_hz = spec.haptic_options.tick_hz;
    const std::uint64_t first = haptics::seconds_to_tick(spec.from_us, tick_hz);
    const std::uint64_t end = haptics::seconds_to_tick(audio_end_us, tick_hz) + 2;
    const auto notes = spec.haptic->device_notes();
    std::vector<float> signal =
        haptics::render_signal(notes, spec.haptic->uploads, haptics::render_settings(spec.haptic_options), first, end);
    std::vector<float> audible = audio::resample(signal, static_cast<int>(tick_hz), spec.encoding.sample_rate);
    fit(audible, samples);
    streams.push_back(std::move(audible));
    channels.push_back(1);
  }
  result.audio_wall_s = seconds_since(audio_started);

  VideoSetup setup = spec.encoding;
  setup.audio.clear();
  setup.audio.push_back({2, "song", 192000});
  if (spec.haptic_audio) setup.audio.push_back({1, "haptic signal", 96000});
  output::StagedOutput staged(path);  // the encoder writes PATH.part, renamed to PATH only when complete
  setup.path = staged.part();
  std::unique_ptr<VideoEncoder> encoder = backend->open(setup, why);
  if (!encoder) throw std::runtime_error("cannot write " + path + ": " + why);
  result.encoder = encoder->summary();

  // Drawing here, encoding on a thread of its own (libx264 adds its own threads).
  const std::size_t frame_bytes = i420_bytes(spec.encoding.width, spec.encoding.height);
  FrameQueue queue(3, frame_bytes);
  std::string encode_error;
  std::atomic<std::uint64_t> encoded{0};
  double encode_wall = 0;
  std::thread encoding([&] {
    const std::size_t spf = result.samples_per_frame;
    for (std::uint64_t i = 0;; ++i) {
      std::vector<std::uint8_t> frame = queue.take_full();
      if (frame.empty()) break;
      const auto t0 = WallClock::now();
      const I420Planes p = i420_planes(frame.data(), spec.encoding.width, spec.encoding.height);
      bool ok = encoder->add_frame_i420(p.y, p.u, p.v);
      std::size_t at = 0;
      for (std::size_t s = 0; ok && s < channels.size(); ++s) {
        const float* planes[2] = {streams[at].data() + i * spf, nullptr};
        if (channels[s] == 2) planes[1] = streams[at + 1].data() + i * spf;
        ok = encoder->add_audio(static_cast<int>(s), planes, spf);
        at += static_cast<std::size_t>(channels[s]);
      }
      encode_wall += seconds_since(t0);
      queue.put_free(std::move(frame));
      if (!ok) {
        encode_error = encoder->error();
        queue.abort();
        return;
      }
      encoded.store(i + 1);
    }
    const auto t0 = WallClock::now();
    if (!encoder->finish()) encode_error = encoder->error();
    encode_wall += seconds_since(t0);
  });

  const haptics::SignalTail tail(spec.haptic, spec.haptic_options);
  double render_wall = 0;
  bool cancelled = false;
  for (std::uint64_t i = 0; i < result.frames; ++i) {
    if (spec.cancel != nullptr && spec.cancel->load()) {
      cancelled = true;
      queue.abort();
      break;
    }
    const auto t0 = WallClock::now();
    const std::uint8_t* pixels =
        frames->draw(video_frame_state(spec, tail, frame_time_us(spec.from_us, i, spec.encoding.fps)));
    std::vector<std::uint8_t> buffer = queue.take_free();
    if (buffer.empty()) break;  // the encoder stopped
    rgba_bottom_up_to_i420(pixels, spec.encoding.width, spec.encoding.height,
                           i420_planes(buffer.data(), spec.encoding.width, spec.encoding.height));
    render_wall += seconds_since(t0);
    queue.put_full(std::move(buffer));
    if (progress) progress(encoded.load(), result.frames);
  }
  queue.close();
  encoding.join();
  if (cancelled) throw std::runtime_error("interrupted: " + path + " not written");
  if (!encode_error.empty()) throw std::runtime_error("cannot write " + path + ": " + encode_error);
  if (progress) progress(result.frames, result.frames);
  staged.commit();
  result.render_wall_s = render_wall;
  result.encode_wall_s = encode_wall;
  result.wall_s = seconds_since(started);
  return result;
}

}  // namespace hmp::video
