#include "host/audio/audio_player.hpp"

#include <algorithm>
#include <cmath>
#include <thread>
#include <utility>

#include "host/audio/soundfont.hpp"

namespace hmp::audio {

namespace {

// busy_ (audio_player.hpp) for the lifetime of a scope.
struct BusyFlag {
  explicit BusyFlag(std::atomic<bool>& flag) : flag_(flag) { flag_.store(true); }
  ~BusyFlag() { flag_.store(false); }
  BusyFlag(const BusyFlag&) = delete;
  BusyFlag& operator=(const BusyFlag&) = delete;
  std::atomic<bool>& flag_;
};

}  // namespace

AudioPlayer::AudioPlayer(const AudioOptions& options, WarningSink warn) : options_(options), warn_(std::move(warn)) {
  if (!options_.enabled) {
    go_silent("audio disabled (--no-audio)", false);
    return;
  }
  const std::optional<std::string> soundfont = find_soundfont(options_.soundfont);
  if (!soundfont) {
    go_silent(options_.soundfont.empty() ? "no General MIDI SoundFont found (install fluid-soundfont-gm)"
                                         : "SoundFont " + options_.soundfont + " not found",
              true);
    return;
  }
  std::string why;
  backend_ = audio_backend(&why);
  if (backend_ == nullptr) {
    go_silent("the audio module is not available (" + why + ")", true);
    return;
  }
  synth_ = backend_->make_synth(options_.synth);
  if (!synth_) {
    go_silent("FluidSynth could not create a synthesizer", true);
    return;
  }
  // The driver first (cheap to try, and usually what is missing), the SoundFont only for a driver.
  if (!open_driver()) return;
  bool loaded = false;
  {
    const BusyFlag busy(busy_);
    std::lock_guard lock(mutex_);  // the callback renders nothing while not playing; this is belt and braces
    loaded = synth_->load_soundfont(*soundfont);
  }
  if (!loaded) go_silent(synth_->load_error(), true);
}

AudioPlayer::~AudioPlayer() {
  card_.reset();    // its thread calls render(): stopped before anything it uses goes
  output_.reset();  // likewise the driver's
}

void AudioPlayer::go_silent(std::string reason, bool warn_user) {
  card_.reset();
  output_.reset();
  synth_.reset();
  driver_name_ = "none";
  silence_reason_ = std::move(reason);
  if (warn_user && warn_) warn_("audio: " + silence_reason_ + ": playing without sound");
}

bool AudioPlayer::open_driver() {
  std::string tried;
  for (const std::string& name : options_.drivers) {
    if (name == "virtual") {
      const int period = options_.virtual_period_frames > 0 ? options_.virtual_period_frames : options_.period_frames;
      VirtualCard::Settings card{options_.synth.sample_rate, period, options_.periods, options_.virtual_ppm,
                                 options_.virtual_record_frames};
      card_ = std::make_unique<VirtualCard>(card, [this](float* left, float* right, int frames) {
        float* out[2] = {left, right};
        render(frames, 2, out);
      });
      driver_name_ = name;
      return true;
    }
    std::string error;
    output_ = backend_->open_output(*synth_, name, options_.period_frames, options_.periods, &AudioPlayer::on_audio,
                                    this, error);
    if (output_) {
      driver_name_ = name;
      return true;
    }
    tried += (tried.empty() ? "" : "; ") + name + (error.empty() ? "" : ": " + error);
  }
  go_silent("no audio output could be opened (" + (tried.empty() ? std::string("no driver to try") : tried) + ")",
            true);
  return false;
}

std::chrono::steady_clock::duration AudioPlayer::latency() const {
  return std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(output_latency_s()));
}

double AudioPlayer::output_latency_s() const {
  if (!audible()) return 0.0;
  const int seen = period_seen_.load();
  const int period = seen > 0 ? seen : options_.period_frames;
  return static_cast<double>(period) * options_.periods / options_.synth.sample_rate;
}

bool AudioPlayer::wait_for_first_callback(std::chrono::milliseconds timeout) const {
  if (!audible()) return false;
  const TimePoint until = now() + timeout;
  while (period_seen_.load() == 0) {
    if (now() >= until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return true;
}

double AudioPlayer::clock_speed() const {
  std::lock_guard lock(mutex_);
  return clock_.speed();
}

std::uint64_t AudioPlayer::clock_restarts() const {
  std::lock_guard lock(mutex_);
  return clock_.restarts();
}

void AudioPlayer::on_audio(void* self, int len, int nout, float* out[]) {
  static_cast<AudioPlayer*>(self)->render(len, nout, out);
}

void AudioPlayer::render(int len, int nout, float* out[]) {
  const TimePoint called = now();
  callbacks_.fetch_add(1);
  period_seen_.store(len);
  if (busy_.load()) return;  // the driver zeroed the buffers
  std::lock_guard lock(mutex_);
  if (!playing_ || !synth_ || nout < 1 || len <= 0) return;  // the driver zeroed the buffers
  float* right = nout >= 2 ? out[1] : nullptr;
  if (right == nullptr) {
    spare_.resize(static_cast<std::size_t>(len));
    right = spare_.data();
  }
  // This buffer's first sample is heard once the buffers queued ahead of it have played.
  clock_.set_buffer_us(output_latency_s() * 1e6);
  clock_.observe(synth_->position_us(), called + latency());
  synth_->render(out[0], right, static_cast<std::size_t>(len));
}

std::int64_t AudioPlayer::to_play(std::int64_t song_us) const {
  return speed_ == 1.0 ? song_us : std::llround(static_cast<double>(song_us) / speed_);
}

std::int64_t AudioPlayer::to_song(std::int64_t play_us) const {
  return speed_ == 1.0 ? play_us : std::llround(static_cast<double>(play_us) * speed_);
}

void AudioPlayer::load_events() {
  if (!synth_) return;
  if (speed_ == 1.0) {
    synth_->set_events(events_);
    return;
  }
  std::vector<AudioEvent> scaled = events_;
  for (AudioEvent& e : scaled) e.time_us = to_play(e.time_us);
  synth_->set_events(scaled);
}

void AudioPlayer::set_events(const std::vector<AudioEvent>& events) {
  const BusyFlag busy(busy_);
  std::lock_guard lock(mutex_);
  playing_ = false;
  clock_.pause(now());
  clock_.set_paused_position(0);
  events_ = events;
  load_events();
}

void AudioPlayer::play_now(const AudioEvent& e) {
  std::lock_guard lock(mutex_);
  if (synth_) synth_->apply_now(e);
}

void AudioPlayer::start_locked(std::int64_t song_us) {
  if (synth_) synth_->seek(to_play(song_us));
  clock_.start(to_play(song_us), now() + latency());
  playing_ = true;
}

void AudioPlayer::start(std::int64_t song_us) {
  std::lock_guard lock(mutex_);
  start_locked(song_us);
}

void AudioPlayer::pause() {
  std::lock_guard lock(mutex_);
  if (!playing_) return;
  playing_ = false;
  clock_.pause(now());
  if (synth_) synth_->release_all();
}

void AudioPlayer::resume() {
  std::lock_guard lock(mutex_);
  if (playing_) return;
  start_locked(to_song(clock_.song_us(now())));
}

void AudioPlayer::seek(std::int64_t song_us) {
  std::lock_guard lock(mutex_);
  if (playing_) {
    start_locked(song_us);
    return;
  }
  if (synth_) synth_->seek(to_play(song_us));
  clock_.set_paused_position(to_play(song_us));
}

void AudioPlayer::set_speed(double speed) {
  speed = std::clamp(speed, 0.5, 2.0);
  std::lock_guard lock(mutex_);
  if (speed == speed_) return;
  const std::int64_t at = to_song(clock_.song_us(now()));
  speed_ = speed;
  load_events();  // the events at the new pace (the synthesizer stops; playing restarts just below)
  if (playing_) {
    start_locked(at);
  } else {
    if (synth_) synth_->seek(to_play(at));
    clock_.set_paused_position(to_play(at));
  }
}

double AudioPlayer::speed() const {
  std::lock_guard lock(mutex_);
  return speed_;
}

void AudioPlayer::stop() {
  std::lock_guard lock(mutex_);
  if (playing_) clock_.pause(now());
  playing_ = false;
  if (synth_) synth_->seek(clock_.song_us(now()));  // seek cuts every voice at once (play time, as inside)
}

bool AudioPlayer::playing() const {
  std::lock_guard lock(mutex_);
  return playing_;
}

std::int64_t AudioPlayer::song_time_us(TimePoint t) const {
  std::lock_guard lock(mutex_);
  return to_song(clock_.song_us(t));
}

AudioPlayer::TimePoint AudioPlayer::heard_at(std::int64_t song_us) const {
  std::lock_guard lock(mutex_);
  return clock_.heard_at(to_play(song_us));
}

AudioPlayer::TimePoint AudioPlayer::heard_onset_at(std::uint8_t channel, std::uint8_t program, std::uint8_t key,
                                                   std::int64_t song_us) const {
  std::lock_guard lock(mutex_);
  if (!synth_ || !audible()) return clock_.heard_at(to_play(song_us));
  const std::int64_t frame = synth_->heard_frame(channel, program, key, to_play(song_us));
  // Nearest µs of that frame (the clock counts µs; half a µs is far below anything heard).
  const std::int64_t rate = synth_->sample_rate();
  const std::int64_t scaled = frame * 1'000'000;
  const std::int64_t us = scaled >= 0 ? (scaled + rate / 2) / rate : -((-scaled + rate / 2) / rate);
  return clock_.heard_at(us);
}

}  // namespace hmp::audio
