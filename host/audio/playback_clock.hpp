#pragma once
// The song clock of the audio player (design §10): which song time is being heard now. The scheduler
// maps song time to host time (and from there to device ticks) through it, so haptic notes follow the
// sound, output latency included.
//
// Silent playback runs it on the host's steady clock alone. With a sound card, the audio callback
// reports, for each buffer, the song time of its first sample and when that sample will be heard
// (callback time + output latency). A least-squares line through the last few seconds of such reports
// gives offset and speed, so the clock follows the card's crystal (a 100 ppm card drifts 6 ms a
// minute from the host clock). A callback that runs late (the host was busy) says nothing about when
// the card plays, as long as the card's buffer covered the delay: such reports are left out of the
// fit. A report sooner than the line (callbacks are never early, so the line was late), one later
// than the whole buffer (the card ran dry: an underrun shifted what follows), or a run of late ones
// (the stream restarted later) restarts the fit from that report.
#include <chrono>
#include <cstdint>
#include <deque>

namespace hmp::audio {

class PlaybackClock {
 public:
  using TimePoint = std::chrono::steady_clock::time_point;
  static constexpr std::size_t kWindow = 1024;        // reports in the fit (5.5 s of 256-frame buffers at 48 kHz)
  static constexpr std::size_t kMinFit = 32;          // reports before the fit replaces the nominal line
  static constexpr double kMaxSpeedError = 1e-3;      // no sound card is off by more than 1000 ppm
  static constexpr double kOffLineUs = 2'000;         // farther than this off the line: not in the fit
  static constexpr double kDefaultBufferUs = 20'000;  // the card's buffer until set_buffer_us()

  // Playback (re)starts: song time `song_us` is heard at `heard_at`, then time runs at the speed learnt
  // so far (1 at first).
  void start(std::int64_t song_us, TimePoint heard_at);
  // Stops the clock at its reading for `now`.
  void pause(TimePoint now);
  // While paused: sets the reading.
  void set_paused_position(std::int64_t song_us) { paused_us_ = song_us; }
  bool running() const { return running_; }

  // Song time heard at `t` (before the start of a running clock this is before the start position).
  std::int64_t song_us(TimePoint t) const;
  // Host time at which song time `song_us` is (or was) heard; running clocks only.
  TimePoint heard_at(std::int64_t song_us) const;
  // Report from the audio stream; ignored while paused.
  void observe(std::int64_t song_us, TimePoint heard_at);
  // The card's buffer (the output latency): a report later than this means an underrun.
  void set_buffer_us(double us) { buffer_us_ = us; }
  double speed() const { return slope_; }
  std::uint64_t restarts() const { return restarts_; }

 private:
  void restart_line(std::int64_t song_us, TimePoint heard_at);
  void fit();

  bool running_ = false;
  std::int64_t paused_us_ = 0;
  // Running: song = origin_song_ + offset_ + slope_ × (t − origin_time_) [µs]
  TimePoint origin_time_{};
  std::int64_t origin_song_ = 0;
  double offset_ = 0.0;
  double slope_ = 1.0;
  struct Report {
    double x, y;  // host µs and song µs since the origin
  };
  std::deque<Report> reports_;
  std::uint64_t restarts_ = 0;
  std::size_t off_line_run_ = 0;  // reports in a row left out of the fit
  double buffer_us_ = kDefaultBufferUs;
};

}  // namespace hmp::audio
