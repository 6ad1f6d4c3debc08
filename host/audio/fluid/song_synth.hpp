#pragma once
// Part of the audio module (fluid/). FluidSynth rendering the song's audio events against a sample position it owns
// (design §14). The same object feeds the live audio driver and the offline renderer, so what a test measures offline
// is what the speaker plays.
//
// Timing (design §10: audio-haptic skew ≤ 1 ms):
//  - FluidSynth starts voices only at the start of one of its internal blocks (64 frames, 1.33 ms at
//    48 kHz). render() applies each event at the block boundary nearest its time: ≤ half a block off.
//  - Many GM instruments begin with a few ms of near-silence (sample start, envelope delay: 4.7 ms for
//    FluidR3's nylon guitar). set_events() measures, for every (channel kind, program, key) the song
//    uses, how long after its note-on the sound first reaches −60 dB of its peak (dry, one test note at
//    velocity 100, after one throw-away note: FluidSynth's very first note starts ~0.3 ms later than
//    every later one). With onset compensation on, that note's on and off are scheduled that much
//    earlier, so the sound starts at the note's time — as the haptic note does.
//  - heard_frame() says where each note is heard (block boundary + onset): the player puts the haptic
//    note there, so neither the block grid nor the onsets skew sound and vibration.
//
// Not thread-safe: the live player serialises render() (audio thread) and the control calls.
#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "host/audio/audio_backend.hpp"

struct _fluid_hashtable_t;  // FluidSynth's fluid_settings_t
struct _fluid_synth_t;      // FluidSynth's fluid_synth_t

namespace hmp::audio {

class SongSynth final : public Synth {
 public:
  // `soundfont`: a path to load now (see load_soundfont); empty → none yet (render() writes silence).
  SongSynth(const SynthSettings& settings, const std::string& soundfont);
  ~SongSynth() override;
  SongSynth(const SongSynth&) = delete;
  SongSynth& operator=(const SongSynth&) = delete;

  // Loads a SoundFont (0.3–0.7 s for FluidR3_GM). false: FluidSynth could not load it; the synth stays
  // silent and load_error() says why.
  bool load_soundfont(const std::string& path) override;
  // Replaces the events (sorted as audio_events() returns them), measures onsets when compensation is
  // on, and goes to song time 0.
  void set_events(const std::vector<AudioEvent>& events) override;
  // Moves to `song_us`: sounding voices stop at once; the next notes are those starting at or after it
  // (held notes that started before are not re-struck). FluidSynth's block grid is realigned so that
  // song frames that are multiples of the block are block starts: renders are reproducible.
  void seek(std::int64_t song_us) override;
  // Releases every sounding note (their release phase still plays): pause.
  void release_all() override;
  void apply_now(const AudioEvent& e) override { apply(e); }
  // Writes `frames` frames of the song from the present position into left/right (overwritten) and
  // advances the position by as much. Events due in that stretch are applied on the way.
  void render(float* left, float* right, std::size_t frames) override;

  std::int64_t position_frames() const { return pos_; }  // song frame of the next rendered sample
  std::int64_t position_us() const override;
  std::int64_t frame_of(std::int64_t song_us) const override;  // nearest frame
  int sample_rate() const override { return settings_.sample_rate; }
  int block_frames() const { return block_; }
  bool has_soundfont() const override { return soundfont_id_ >= 0; }
  const std::string& load_error() const override { return load_error_; }
  // The measured onset delay of a note (0 before set_events measured it, or without a SoundFont).
  std::int64_t onset_lead_frames(std::uint8_t channel, std::uint8_t program, std::uint8_t key) const;
  // The song frame at which a note starting at `song_us` is first heard (−60 dB of its peak): its
  // note-on moved earlier by the onset lead, put on the block boundary render() applies it at, plus
  // the lead again. The haptic note is placed there (not at `song_us`), so the block grid adds no
  // audio–haptic skew. Without a SoundFont: frame_of(song_us).
  std::int64_t heard_frame(std::uint8_t channel, std::uint8_t program, std::uint8_t key,
                           std::int64_t song_us) const override;

  _fluid_hashtable_t* fluid_settings() { return fluid_settings_; }

 private:
  struct Timed {
    std::int64_t frame;  // when it is applied: the event's frame minus the note's onset lead
    AudioEvent event;
  };
  static std::uint32_t sound_key(std::uint8_t channel, std::uint8_t program, std::uint8_t key);
  void measure_onsets(const std::vector<AudioEvent>& events);
  std::int64_t measure_onset(std::uint8_t channel, std::uint8_t program, std::uint8_t key);
  void render_scratch(std::size_t frames, float* keep = nullptr);  // off the song timeline
  void warm_up();
  void dispatch_due();  // at a block boundary: applies the events nearest to it
  void apply(const AudioEvent& e);
  void restore_controls(std::size_t before);  // after a seek: the controllers of the events before `before`
  std::int64_t applied_lead(std::uint8_t channel, std::uint8_t program, std::uint8_t key) const;

  SynthSettings settings_;
  _fluid_hashtable_t* fluid_settings_ = nullptr;
  _fluid_synth_t* synth_ = nullptr;
  int initial_cc_[16][128] = {};  // a fresh synthesizer's controllers (restore_controls)
  int initial_bend_range_[16] = {};
  int soundfont_id_ = -1;
  std::string load_error_;
  int block_ = 64;

  std::map<std::uint32_t, std::int64_t> onset_lead_;  // sound_key → frames
  std::int64_t max_lead_ = 0;                         // largest lead applied (0 without compensation)
  bool warmed_up_ = false;                            // the throw-away first note has been played
  std::vector<Timed> events_;
  std::array<int, 16> channel_program_{};  // what FluidSynth's channels are set to (its default: 0)
  std::size_t next_ = 0;                   // first event not applied yet
  std::int64_t pos_ = 0;                   // song frame of the next sample
  std::uint64_t synth_frames_ = 0;         // frames FluidSynth produced: its blocks start at multiples of block_
};

}  // namespace hmp::audio
