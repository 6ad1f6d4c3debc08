#pragma once
// The song's audio during `hmp play` (design §14): FluidSynth with the GM SoundFont on the first audio
// driver that opens (pulseaudio, alsa, sdl2; or "virtual", a simulated card: virtual_card.hpp), rendering from the
// audio callback, sample-accurately against a song position it owns; a PlaybackClock tells the rest of the player which
// song time is being heard. Without audio (`--no-audio`, no SoundFont, no sound device) the same clock runs on the host
// clock and nothing is rendered: one warning says why (none for --no-audio), and nothing else of FluidSynth's or ALSA's
// reaches stderr.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "host/audio/pi_mutex.hpp"

#include "host/audio/audio_events.hpp"
#include "host/audio/audio_options.hpp"
#include "host/audio/playback_clock.hpp"
#include "host/audio/audio_backend.hpp"
#include "host/audio/virtual_card.hpp"

namespace hmp::audio {

class AudioPlayer {
 public:
  using TimePoint = PlaybackClock::TimePoint;

  explicit AudioPlayer(const AudioOptions& options, WarningSink warn = print_warning);
  ~AudioPlayer();
  AudioPlayer(const AudioPlayer&) = delete;
  AudioPlayer& operator=(const AudioPlayer&) = delete;

  // The song's events (audio_events()); stops playback and goes to song time 0. With a SoundFont this
  // also measures the instruments' onsets (song_synth.hpp): tens of ms for a whole GM song.
  void set_events(const std::vector<AudioEvent>& events);

  // Plays from `song_us`. The clock says `song_us` once the first sample is heard, output latency later.
  void start(std::int64_t song_us);
  // Stops the sound (notes are released) and the clock, at the song time being heard now.
  void pause();
  // Continues from where pause() stopped.
  void resume();
  // Moves to `song_us`, playing or paused as before.
  void seek(std::int64_t song_us);
  // Stops at once (no release tails); the position stays.
  void stop();
  // One event heard at once, whatever the song's position (`hmp live`'s input); nothing when silent.
  void play_now(const AudioEvent& e);
  // Playback speed (0.5–2; 1 = the song's own pace): the song's events come that much faster, at their
  // own pitch (the synthesizer plays them, nothing is resampled). Takes effect at once from the present
  // position, playing or paused. Every time in this interface stays song time; inside, the synthesizer
  // and the clock run on "play time" = song time / speed.
  void set_speed(double speed);
  double speed() const;
  bool playing() const;

  // The clock: song time heard at `t` (now by default), and its inverse.
  std::int64_t song_time_us(TimePoint t = std::chrono::steady_clock::now()) const;
  TimePoint heard_at(std::int64_t song_us) const;
  // When the sound of a note starting at `song_us` is heard: at FluidSynth's block boundary for its
  // note-on plus its onset (SongSynth::heard_frame), so a haptic note placed there meets the sound
  // whatever the block grid. Silent: heard_at(song_us).
  TimePoint heard_onset_at(std::uint8_t channel, std::uint8_t program, std::uint8_t key, std::int64_t song_us) const;
  // Output latency estimate: period × periods / sample rate, the period being what the driver's
  // callbacks actually ask for (the requested one until the first callback). 0 when silent.
  double output_latency_s() const;
  // Waits, at most `timeout`, for the driver's first callback after start(), from which on
  // output_latency_s() is the period the driver uses. False if none came (or silent).
  bool wait_for_first_callback(std::chrono::milliseconds timeout) const;
  // Song µs per host µs the clock has learnt (1 + the card's crystal error, seen from the host).
  double clock_speed() const;
  std::uint64_t clock_restarts() const;  // times the clock's line started again (PlaybackClock::restarts)

  bool audible() const { return output_ != nullptr || card_ != nullptr; }  // a driver runs, a SoundFont is loaded
  const std::string& driver_name() const { return driver_name_; }          // "pulseaudio", …, or "none"
  const std::string& silence_reason() const { return silence_reason_; }    // empty when audible
  std::uint64_t callbacks() const { return callbacks_.load(); }
  const VirtualCard* virtual_card() const { return card_.get(); }  // the "virtual" driver, else null

 private:
  static void on_audio(void* self, int len, int nout, float* out[]);
  void render(int len, int nout, float* out[]);
  bool open_driver();
  // `reason` by value: it may be the synthesizer's own text (load_error()), which goes with it.
  void go_silent(std::string reason, bool warn_user);
  TimePoint now() const { return std::chrono::steady_clock::now(); }
  std::chrono::steady_clock::duration latency() const;

  AudioOptions options_;
  WarningSink warn_;
  const AudioBackend* backend_ = nullptr;  // the audio module; null when silent
  std::unique_ptr<Synth> synth_;           // null when silent
  std::unique_ptr<OutputStream> output_;   // a sound card's driver, or null
  std::unique_ptr<VirtualCard> card_;      // instead of output_ for the "virtual" driver
  std::string driver_name_ = "none";
  std::string silence_reason_;

  // synth_, clock_, playing_ between the control calls and the audio thread (which must not wait behind an
  // ordinary thread the load preempted: priority inheritance)
  mutable PiMutex mutex_;
  PlaybackClock clock_;  // in play time
  double speed_ = 1.0;
  std::vector<AudioEvent> events_;  // in song time
  std::int64_t to_play(std::int64_t song_us) const;
  std::int64_t to_song(std::int64_t play_us) const;
  void load_events();  // events_ at the present speed into the synthesizer
  void start_locked(std::int64_t song_us);
  bool playing_ = false;
  std::atomic<int> period_seen_{0};  // frames per callback the driver actually uses
  std::atomic<std::uint64_t> callbacks_{0};
  // Set while a long job holds mutex_ with nothing playing (loading the SoundFont, measuring a song's
  // onsets): the callback then returns silence at once instead of waiting for the lock, which would
  // make the card run dry (an underrun) for a period that was silent anyway.
  std::atomic<bool> busy_{false};
  std::vector<float> spare_;  // right channel when a driver hands out a single buffer
};

}  // namespace hmp::audio
