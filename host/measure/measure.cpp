#include "host/measure/measure.hpp"

#include <cmath>

#include "host/audio/offline_render.hpp"
#include "host/common/error.hpp"

namespace hmp::measure {

namespace {

constexpr int kRate = 48000;
constexpr int kBlock = 64;              // FluidSynth's block: events land on its boundaries
constexpr double kLoudAtRelease = 0.1;  // a second render releases the note at −20 dB

struct Note {
  std::uint8_t program;
  std::uint8_t key;
  double off_s;  // after the note-on, on a block boundary
};

double on_block(double s) { return std::round(s * kRate / kBlock) * kBlock / kRate; }

// Every note in its own slot of one render; each slot starts on a block boundary with all sound off, so
// a long release of the note before cannot leak in. Returns the notes' envelopes.
std::vector<SoundEnvelope> render(const MeasureOptions& o, const std::vector<Note>& notes) {
  const double slot_s = on_block(o.hold_s + o.release_window_s + 0.1);
  std::vector<audio::AudioEvent> events;
  for (std::size_t i = 0; i < notes.size(); ++i) {
    const auto at_us = [&](double s) { return std::llround((static_cast<double>(i) * slot_s + s) * 1e6); };
    audio::AudioEvent quiet;
    quiet.kind = audio::AudioEvent::Kind::control;
    quiet.control = midi::Control::Kind::controller;
    quiet.key = 120;  // all sound off
    quiet.time_us = at_us(0);
    events.push_back(quiet);
    audio::AudioEvent on;
    on.kind = audio::AudioEvent::Kind::note_on;
    on.key = notes[i].key;
    on.velocity = o.velocity;
    on.program = notes[i].program;
    on.time_us = at_us(0);
    events.push_back(on);
    audio::AudioEvent off = on;
    off.kind = audio::AudioEvent::Kind::note_off;
    off.velocity = 0;
    off.time_us = at_us(notes[i].off_s);
    events.push_back(off);
  }
  audio::AudioOptions options;
  options.soundfont = o.soundfont;
  options.synth.sample_rate = kRate;
  options.synth.reverb = false;  // the instrument's envelope, not the room's tail
  options.synth.chorus = false;
  options.synth.onset_compensation = false;  // notes start at their own time: the delay is measured
  std::string warning;
  const audio::RenderedAudio audio =
      audio::render_offline(events, 0, std::llround(slot_s * static_cast<double>(notes.size()) * 1e6), options,
                            [&](const std::string& w) { warning = w; });
  if (audio.silent_fallback) throw BadInput(o.soundfont + ": " + warning);
  std::vector<SoundEnvelope> out;
  const auto slot_frames = static_cast<std::size_t>(std::llround(slot_s * kRate));
  for (std::size_t i = 0; i < notes.size(); ++i) {
    const std::size_t at = i * slot_frames;
    const std::size_t frames = std::min(slot_frames, audio.left.size() - std::min(at, audio.left.size()));
    out.push_back(envelope_of(audio.left.data() + at, audio.right.data() + at, frames, kRate, key_hz(notes[i].key),
                              notes[i].off_s));
  }
  return out;
}

}  // namespace

double key_hz(std::uint8_t key) { return 440.0 * std::pow(2.0, (key - 69) / 12.0); }

std::vector<Measured> measure_programs(const MeasureOptions& o,
                                       const std::function<void(const std::string&)>& progress) {
  std::vector<Note> held;
  for (std::uint8_t p : o.programs) held.push_back({p, o.key, on_block(o.hold_s)});
  if (progress) progress("rendering " + std::to_string(held.size()) + " held note(s)");
  const std::vector<SoundEnvelope> envelopes = render(o, held);
  std::vector<Measured> out(held.size());
  for (std::size_t i = 0; i < held.size(); ++i) {
    out[i].program = held[i].program;
    out[i].key = held[i].key;
    out[i].held = envelopes[i];
    out[i].stages = fit_stages(envelopes[i]);
  }
  // An instrument whose samples do not reach the key (a contrabass at middle C) is tried an octave or
  // two lower, then higher, unless the key was asked for.
  for (int shift : {-12, -24, 12, 24}) {
    if (!o.key_fallback) break;
    std::vector<std::size_t> silent;
    for (std::size_t i = 0; i < out.size(); ++i) {
      if (!out[i].stages.sounded) silent.push_back(i);
    }
    const int key = o.key + shift;
    if (silent.empty() || key < 0 || key > 127) continue;
    std::vector<Note> retry;
    for (std::size_t i : silent) retry.push_back({held[i].program, static_cast<std::uint8_t>(key), held[i].off_s});
    if (progress)
      progress("rendering " + std::to_string(retry.size()) + " silent note(s) at key " + std::to_string(key));
    const std::vector<SoundEnvelope> again = render(o, retry);
    for (std::size_t k = 0; k < silent.size(); ++k) {
      Measured& m = out[silent[k]];
      m.key = retry[k].key;
      m.held = again[k];
      m.stages = fit_stages(again[k]);
    }
  }

  // A note that has died away before its note-off shows no release: rendered again, released loud.
  std::vector<Note> early;
  std::vector<std::size_t> early_of;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const Measured& m = out[i];
    if (!m.stages.sounded || !std::isnan(m.stages.release_s)) continue;
    const double t = time_to_fall_to(m.held, m.stages, kLoudAtRelease);
    if (std::isfinite(t) && t > 0.01) {
      early.push_back({m.program, m.key, on_block(t)});
      early_of.push_back(i);
    }
  }
  if (!early.empty()) {
    if (progress) progress("rendering " + std::to_string(early.size()) + " note(s) released early, for their release");
    const std::vector<SoundEnvelope> released = render(o, early);
    for (std::size_t k = 0; k < early.size(); ++k) {
      Measured& m = out[early_of[k]];
      m.stages.release_s = release_of(released[k]);
      m.release_from_second_render = true;
    }
  }
  for (Measured& m : out) {
    if (m.stages.sounded) m.preset = fit_adsr(m.held, m.stages, &m.rms_error);
  }
  return out;
}

}  // namespace hmp::measure
