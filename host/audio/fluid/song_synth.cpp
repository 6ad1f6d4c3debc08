#include "host/audio/fluid/song_synth.hpp"

#include <fluidsynth.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "host/audio/fluid/fluid_runtime.hpp"
#include "host/audio/soundfont.hpp"

namespace hmp::audio {

namespace {
constexpr int kCalibrationVelocity = 100;
constexpr float kOnsetThreshold = 1e-3f;  // −60 dB of the test note's peak
constexpr double kCalibrationWindowMs = 40.0;
}  // namespace

SongSynth::SongSynth(const SynthSettings& settings, const std::string& soundfont) : settings_(settings) {
  install_fluid_logging();
  fluid_settings_ = new_fluid_settings();
  if (fluid_settings_ == nullptr) throw std::runtime_error("FluidSynth: cannot create settings");
  fluid_settings_setnum(fluid_settings_, "synth.sample-rate", static_cast<double>(settings_.sample_rate));
  fluid_settings_setnum(fluid_settings_, "synth.gain", static_cast<double>(settings_.gain));
  fluid_settings_setint(fluid_settings_, "synth.reverb.active", settings_.reverb ? 1 : 0);
  fluid_settings_setint(fluid_settings_, "synth.chorus.active", settings_.chorus ? 1 : 0);
  fluid_settings_setint(fluid_settings_, "synth.cpu-cores", 1);  // render in the caller's thread only
  synth_ = new_fluid_synth(fluid_settings_);
  if (synth_ == nullptr) {
    delete_fluid_settings(fluid_settings_);
    throw std::runtime_error("FluidSynth: cannot create a synthesizer");
  }
  block_ = fluid_synth_get_internal_bufsize(synth_);
  // The channels' controllers as a fresh synthesizer has them: what a seek restores before replaying the
  // song's own (FluidSynth's defaults, e.g. its reverb send, not guessed here).
  for (int channel = 0; channel < 16; ++channel) {
    for (int cc = 0; cc < 128; ++cc) fluid_synth_get_cc(synth_, channel, cc, &initial_cc_[channel][cc]);
    fluid_synth_get_pitch_wheel_sens(synth_, channel, &initial_bend_range_[channel]);
  }
  if (!soundfont.empty()) load_soundfont(soundfont);
}

bool SongSynth::load_soundfont(const std::string& path) {
  if (const std::string problem = soundfont_format_problem(path); !problem.empty()) {
    load_error_ = "cannot load SoundFont " + path + " (" + problem + ")";
    return false;
  }
  take_fluid_messages();  // only this load's complaints go into load_error_
  const int id = fluid_synth_sfload(synth_, path.c_str(), 1);
  if (id == FLUID_FAILED) {
    const std::vector<std::string> log = take_fluid_messages();
    load_error_ = "cannot load SoundFont " + path + (log.empty() ? "" : " (" + log.back() + ")");
    return false;
  }
  soundfont_id_ = id;
  load_error_.clear();
  return true;
}

SongSynth::~SongSynth() {
  delete_fluid_synth(synth_);
  delete_fluid_settings(fluid_settings_);
}

std::int64_t SongSynth::frame_of(std::int64_t song_us) const { return nearest_frame(song_us, settings_.sample_rate); }

std::int64_t SongSynth::position_us() const { return pos_ * 1'000'000 / settings_.sample_rate; }

std::uint32_t SongSynth::sound_key(std::uint8_t channel, std::uint8_t program, std::uint8_t key) {
  // Channel 9 plays drum kits: the same program number is another sound there.
  const std::uint32_t drums = channel == midi::kDrumChannel ? 1u : 0u;
  return drums << 16 | static_cast<std::uint32_t>(program) << 8 | key;
}

std::int64_t SongSynth::onset_lead_frames(std::uint8_t channel, std::uint8_t program, std::uint8_t key) const {
  const auto it = onset_lead_.find(sound_key(channel, program, key));
  return it == onset_lead_.end() ? 0 : it->second;
}

std::int64_t SongSynth::heard_frame(std::uint8_t channel, std::uint8_t program, std::uint8_t key,
                                    std::int64_t song_us) const {
  if (!has_soundfont()) return frame_of(song_us);
  const std::int64_t applied = frame_of(song_us) - applied_lead(channel, program, key);
  // dispatch_due(): frame f is applied at the boundary b with b − block/2 ≤ f < b + block/2.
  const std::int64_t shifted = applied + block_ / 2;
  const std::int64_t boundary = (shifted >= 0 ? shifted / block_ : -((-shifted + block_ - 1) / block_)) * block_;
  return boundary + onset_lead_frames(channel, program, key);
}

std::int64_t SongSynth::applied_lead(std::uint8_t channel, std::uint8_t program, std::uint8_t key) const {
  return settings_.onset_compensation ? onset_lead_frames(channel, program, key) : 0;
}

void SongSynth::set_events(const std::vector<AudioEvent>& events) {
  if (has_soundfont()) measure_onsets(events);

  // Each note-off goes with the note-on of its (channel, key) before it: both move by that note's lead.
  events_.clear();
  events_.reserve(events.size());
  std::array<std::int64_t, 16 * 128> lead_of_key{};
  std::array<std::ptrdiff_t, 16 * 128> last_off;
  last_off.fill(-1);
  for (const AudioEvent& e : events) {
    if (e.kind == AudioEvent::Kind::control) {  // on time (a note's lead moves its sound's onset only)
      events_.push_back({frame_of(e.time_us), e});
      continue;
    }
    const std::size_t slot = static_cast<std::size_t>(e.channel & 0x0F) * 128 + (e.key & 0x7F);
    if (e.kind == AudioEvent::Kind::note_on) {
      lead_of_key[slot] = applied_lead(e.channel, e.program, e.key);
      const std::int64_t frame = frame_of(e.time_us) - lead_of_key[slot];
      // A re-struck key whose new lead is larger must not be cut by the previous note's off.
      if (last_off[slot] >= 0) {
        Timed& off = events_[static_cast<std::size_t>(last_off[slot])];
        off.frame = std::min(off.frame, frame);
      }
      events_.push_back({frame, e});
    } else {
      last_off[slot] = static_cast<std::ptrdiff_t>(events_.size());
      events_.push_back({frame_of(e.time_us) - lead_of_key[slot], e});
    }
  }
  std::stable_sort(events_.begin(), events_.end(), [](const Timed& a, const Timed& b) {
    return a.frame != b.frame ? a.frame < b.frame : a.event.kind < b.event.kind;
  });
  seek(0);
}

void SongSynth::measure_onsets(const std::vector<AudioEvent>& events) {
  if (!warmed_up_) {
    warm_up();
    warmed_up_ = true;
  }
  for (const AudioEvent& e : events) {
    if (e.kind != AudioEvent::Kind::note_on) continue;
    const std::uint32_t k = sound_key(e.channel, e.program, e.key);
    if (onset_lead_.count(k) == 0) onset_lead_[k] = measure_onset(e.channel, e.program, e.key);
  }
  max_lead_ = 0;
  if (settings_.onset_compensation) {
    for (const auto& [key, lead] : onset_lead_) max_lead_ = std::max(max_lead_, lead);
  }
}

void SongSynth::render_scratch(std::size_t frames, float* keep) {
  if (frames == 0) return;
  std::vector<float> left(frames), right(frames);
  fluid_synth_write_float(synth_, static_cast<int>(frames), left.data(), 0, 1, right.data(), 0, 1);
  synth_frames_ += frames;
  if (keep != nullptr) {
    for (std::size_t i = 0; i < frames; ++i) keep[i] = std::fabs(left[i]) + std::fabs(right[i]);
  }
}

void SongSynth::warm_up() {
  // A voice of FluidSynth's pool starts ~0.3 ms late the first time it is used (then never again):
  // every voice is used once, with a chord of every key on two programs, before anything is measured
  // or played. Stereo samples take two voices a note.
  fluid_synth_all_sounds_off(synth_, -1);
  const int voices = fluid_synth_get_polyphony(synth_);
  int started = 0;
  for (int channel = 0; channel < 16 && started < voices; ++channel) {
    if (channel == midi::kDrumChannel) continue;
    for (int key = 0; key < 128 && started < voices; ++key, ++started) fluid_synth_noteon(synth_, channel, key, 1);
  }
  render_scratch(static_cast<std::size_t>(block_) * 4);
  fluid_synth_all_sounds_off(synth_, -1);
  render_scratch(static_cast<std::size_t>(block_));
}

std::int64_t SongSynth::measure_onset(std::uint8_t channel, std::uint8_t program, std::uint8_t key) {
  // Dry and alone: effects off, every voice stopped, the note struck exactly on a block boundary.
  fluid_synth_reverb_on(synth_, -1, 0);
  fluid_synth_chorus_on(synth_, -1, 0);
  fluid_synth_all_sounds_off(synth_, -1);
  const auto block = static_cast<std::uint64_t>(block_);
  render_scratch(static_cast<std::size_t>(block + (block - synth_frames_ % block) % block));
  apply({0, AudioEvent::Kind::note_on, channel, key, kCalibrationVelocity, program});
  const auto window = static_cast<std::size_t>(kCalibrationWindowMs * 1e-3 * settings_.sample_rate);
  std::vector<float> level(window);
  render_scratch(window, level.data());
  fluid_synth_all_sounds_off(synth_, -1);
  render_scratch(static_cast<std::size_t>(block));
  fluid_synth_reverb_on(synth_, -1, settings_.reverb ? 1 : 0);
  fluid_synth_chorus_on(synth_, -1, settings_.chorus ? 1 : 0);

  const float peak = *std::max_element(level.begin(), level.end());
  if (!(peak > 0.0f)) return 0;  // a key the instrument does not play
  const auto first = std::find_if(level.begin(), level.end(), [&](float v) { return v >= kOnsetThreshold * peak; });
  const auto lead = static_cast<std::int64_t>(first - level.begin());
  const auto max_lead = static_cast<std::int64_t>(settings_.max_onset_lead_ms * 1e-3 * settings_.sample_rate);
  return std::min(lead, max_lead);
}

void SongSynth::seek(std::int64_t song_us) {
  fluid_synth_all_sounds_off(synth_, -1);
  // FluidSynth frees the stopped voices at its next render; until then lifting the pedal (the reset
  // below) would start their release again and a pedalled note would ring on. One whole block keeps the
  // block phase.
  render_scratch(block_);
  pos_ = frame_of(song_us);
  const auto block = static_cast<std::int64_t>(block_);
  const std::int64_t phase =
      (pos_ - static_cast<std::int64_t>(synth_frames_ % static_cast<std::uint64_t>(block))) % block;
  render_scratch(static_cast<std::size_t>((phase + block) % block));
  // Events are ordered by their (lead-shifted) frames: a note starting right at song_us may sit up to
  // max_lead_ frames earlier, so start looking there.
  const std::int64_t from = pos_ - max_lead_;
  next_ = static_cast<std::size_t>(std::lower_bound(events_.begin(), events_.end(), from,
                                                    [](const Timed& t, std::int64_t f) { return t.frame < f; }) -
                                   events_.begin());
  restore_controls(next_);
}

void SongSynth::restore_controls(std::size_t before) {
  // The channels as the song has them at the new position: every controller, bend and pressure back to
  // its default, then the last value of each before the position (pedal down, volume, pan, bend range…).
  for (int channel = 0; channel < 16; ++channel) {
    fluid_synth_cc(synth_, channel, 121, 0);  // reset all controllers (not volume, pan, sends, bend range)
    for (const std::uint8_t cc : midi::kSoundControllers) {
      if (cc < 120 && cc != 6 && cc != 38 && cc != 100 && cc != 101) {  // not the modes, nor RPN data (it would apply)
        fluid_synth_cc(synth_, channel, cc, initial_cc_[channel][cc]);
      }
    }
    fluid_synth_pitch_wheel_sens(synth_, channel, initial_bend_range_[channel]);
    fluid_synth_pitch_bend(synth_, channel, 8192);
    fluid_synth_channel_pressure(synth_, channel, 0);
  }
  // Replayed in order: RPN selects and data entry must arrive as they did (the bend range).
  for (std::size_t i = 0; i < before; ++i) {
    const AudioEvent& e = events_[i].event;
    if (e.kind != AudioEvent::Kind::control || e.control == midi::Control::Kind::program) continue;
    if (e.control == midi::Control::Kind::controller && (e.key == 120 || e.key == 123)) continue;  // momentary
    apply(e);
  }
}

void SongSynth::release_all() { fluid_synth_all_notes_off(synth_, -1); }

void SongSynth::apply(const AudioEvent& e) {
  if (e.kind == AudioEvent::Kind::note_off) {
    fluid_synth_noteoff(synth_, e.channel, e.key);
    return;
  }
  if (e.kind == AudioEvent::Kind::control) {
    switch (e.control) {
      case midi::Control::Kind::controller: fluid_synth_cc(synth_, e.channel, e.key, e.value); break;
      case midi::Control::Kind::pitch_bend: fluid_synth_pitch_bend(synth_, e.channel, e.value); break;
      case midi::Control::Kind::pressure: fluid_synth_channel_pressure(synth_, e.channel, e.value); break;
      case midi::Control::Kind::program: break;  // each note-on carries its program (below)
    }
    return;
  }
  // The program travels with each note: switching the channel just before the note keeps every note on
  // its own program whatever order the lead shifts put the events in.
  int& program = channel_program_[e.channel & 0x0F];
  if (program != e.program) {
    fluid_synth_program_change(synth_, e.channel, e.program);
    program = e.program;
  }
  fluid_synth_noteon(synth_, e.channel, e.key, e.velocity);
}

void SongSynth::dispatch_due() {
  // An event at frame t belongs to the boundary b with b − block/2 ≤ t < b + block/2.
  const std::int64_t half = block_ / 2;
  while (next_ < events_.size() && events_[next_].frame < pos_ + half) apply(events_[next_++].event);
}

void SongSynth::render(float* left, float* right, std::size_t frames) {
  if (!has_soundfont()) {
    std::fill(left, left + frames, 0.0f);
    std::fill(right, right + frames, 0.0f);
    pos_ += static_cast<std::int64_t>(frames);
    return;
  }
  const auto block = static_cast<std::int64_t>(block_);
  const std::int64_t half = block / 2;
  std::size_t done = 0;
  while (done < frames) {
    const auto into_block = static_cast<std::int64_t>(synth_frames_ % static_cast<std::uint64_t>(block));
    if (into_block == 0) dispatch_due();
    // Render up to the first boundary at which the next event becomes due (or to the end).
    std::int64_t n = static_cast<std::int64_t>(frames - done);
    if (next_ < events_.size()) {
      const std::int64_t first_boundary = pos_ + (block - into_block);
      const std::int64_t wait = events_[next_].frame - half - first_boundary;  // due at b once b > frame − half
      const std::int64_t extra_blocks = wait >= 0 ? wait / block + 1 : 0;
      n = std::min(n, (block - into_block) + extra_blocks * block);
    }
    const int len = static_cast<int>(std::min<std::int64_t>(n, 1 << 20));
    fluid_synth_write_float(synth_, len, left + done, 0, 1, right + done, 0, 1);
    done += static_cast<std::size_t>(len);
    pos_ += len;
    synth_frames_ += static_cast<std::uint64_t>(len);
  }
}

}  // namespace hmp::audio
