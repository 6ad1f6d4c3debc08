#include "shared/synth/engine.hpp"

#include <cmath>

#include "shared/common/text.hpp"
#include "shared/synth/frequency.hpp"

namespace hmp::synth {
namespace {

constexpr const char* kPolicyNames[] = {"sum", "highest", "latest"};  // in enum order
constexpr unsigned kPolicyCount = sizeof kPolicyNames / sizeof kPolicyNames[0];

}  // namespace

const char* name(Polyphony p) {
  const auto i = static_cast<unsigned>(p);
  return i < kPolicyCount ? kPolicyNames[i] : "?";
}

bool find_polyphony(const char* label, Polyphony& out) {
  for (unsigned i = 0; i < kPolicyCount; ++i) {
    if (text::iequals(label, kPolicyNames[i])) {
      out = static_cast<Polyphony>(i);
      return true;
    }
  }
  return false;
}

// ---- Limiter -----------------------------------------------------------------------------------------

void Limiter::configure(float release_ms, std::uint32_t tick_hz) {
  const float release_ticks = release_ms * static_cast<float>(tick_hz) * 0.001f;
  // One-pole recovery; τ ≤ 0 (or NaN) recovers at once.
  keep_ = release_ticks > 0.0f ? std::exp(-1.0f / release_ticks) : 0.0f;
  gap_ = 0.0f;
}

float Limiter::process(float x) {
  const float magnitude = std::fabs(x);
  if (!(magnitude <= 3.0e38f)) return 0.0f;  // NaN or ±Inf: never let it reach the motors

  if (gap_ > 0.0f) {
    gap_ *= keep_;
    if (gap_ < 1e-9f) gap_ = 0.0f;  // long since invisible in 1 − gap; avoids denormals
  }
  float gain = 1.0f - gap_;
  if (magnitude * gain > 1.0f) {  // drop at once: the waveform is scaled, never flattened
    gain = 1.0f / magnitude;
    gap_ = 1.0f - gain;
  }
  const float y = x * gain;
  // 1/|x| is rounded, so x·gain can overshoot by an ulp; the clamp only ever trims that ulp.
  return y > 1.0f ? 1.0f : (y < -1.0f ? -1.0f : y);
}

// ---- Engine ------------------------------------------------------------------------------------------

Engine::Engine(const SynthConfig& cfg) {
  for (std::uint8_t i = 0; i < envelope::kBuiltinCount; ++i) {
    slots_[i] = envelope::builtin(static_cast<envelope::Preset>(i));
    slot_used_[i] = true;
  }
  configure(cfg);
}

void Engine::configure(const SynthConfig& cfg) {
  cfg_ = cfg;
  limiter_.configure(cfg.limiter_release_ms, cfg.tick_hz);
}

// Built-in slots are fixed (a host that wants to override one uploads its version to a user slot).
bool Engine::set_preset(std::uint8_t slot, const envelope::Adsr& adsr) {
  if (slot < envelope::kFirstUserSlot || slot >= envelope::kSlotCount || !envelope::valid(adsr)) return false;
  slots_[slot] = adsr;
  slot_used_[slot] = true;
  return true;
}

const envelope::Adsr* Engine::preset(std::uint8_t slot) const {
  return slot < envelope::kSlotCount && slot_used_[slot] ? &slots_[slot] : nullptr;
}

bool Engine::frequency_ok(std::uint32_t freq_q20) const {
  return freq_q20 != 0 &&
         static_cast<std::uint64_t>(freq_q20) * 2 < (static_cast<std::uint64_t>(cfg_.tick_hz) << kFreqFracBits);
}

bool Engine::playable(const Note& note) {
  // Zero duration is a malformed command here (the host always sends N ≥ 1; a held note has none); zero
  // frequency is silence and frequencies at or above Nyquist cannot be synthesised at this tick rate.
  // Amplitude 0 is allowed.
  if (preset(note.preset) == nullptr || (note.duration_ticks == 0 && !note.held) || !frequency_ok(note.freq_q20)) {
    ++counters_.rejected;
    return false;
  }
  return true;
}

Voice& Engine::take_voice() {
  ++counters_.started;
  // The first free voice (a plain scan: the ages are needed only when there is none)…
  for (Voice& v : voices_) {
    if (!v.active()) return v;
  }
  // …or else the oldest one. Ages are counted modulo 2^32 so the order counter may wrap.
  ++counters_.stolen;
  Voice* oldest = &voices_[0];
  std::uint32_t oldest_age = next_order_ - oldest->order();
  for (Voice& v : voices_) {
    const std::uint32_t age = next_order_ - v.order();
    if (age > oldest_age) {
      oldest = &v;
      oldest_age = age;
    }
  }
  return *oldest;
}

bool Engine::start(const Note& note) {
  if (!playable(note)) return false;
  take_voice().start(note, *preset(note.preset), cfg_, next_order_++);
  return true;
}

bool Engine::start_prepared(const Voice& prepared) {
  if (!playable(prepared.note())) return false;
  take_voice().adopt(prepared, next_order_++);
  return true;
}

bool Engine::start_held(Note note) {
  note.held = true;
  if (!playable(note)) return false;
  release(note.track, note.key);
  take_voice().start(note, *preset(note.preset), cfg_, next_order_++);
  return true;
}

bool Engine::release(std::uint8_t track, std::uint8_t key) {
  bool found = false;
  for (Voice& v : voices_) {
    if (v.held() && v.note().track == track && v.note().key == key) {
      v.release();
      found = true;
    }
  }
  return found;
}

bool Engine::bend(std::uint8_t track, std::uint8_t key, std::uint32_t freq_q20) {
  if (!frequency_ok(freq_q20)) return false;
  bool found = false;
  for (Voice& v : voices_) {
    if (v.active() && v.note().held && v.note().track == track && v.note().key == key) {
      v.set_frequency(freq_q20, cfg_.tick_hz);
      found = true;
    }
  }
  return found;
}

float Engine::tick() {
  if (policy_ == Polyphony::sum) {  // the default, and the firmware's hot loop: nothing to choose
    float sum = 0.0f;
    for (Voice& v : voices_) {
      if (v.active()) sum += v.next();
    }
    return limiter_.process(sum);
  }
  float sum = 0.0f;
  float chosen = 0.0f;
  const Voice* best = nullptr;  // the voice the highest/latest policy lets through
  for (Voice& v : voices_) {
    if (!v.active()) continue;
    const bool newer = !best || (next_order_ - v.order()) < (next_order_ - best->order());
    bool pick = false;
    switch (policy_) {
      case Polyphony::sum: break;
      case Polyphony::highest:  // frequency is monotonic in key for every mapping; ties go to the newest
        pick = !best || v.freq_q20() > best->freq_q20() || (v.freq_q20() == best->freq_q20() && newer);
        break;
      case Polyphony::latest: pick = newer; break;
    }
    const float y = v.next();  // every voice advances, heard or not
    sum += y;
    if (pick) {
      best = &v;
      chosen = y;
    }
  }
  return limiter_.process(policy_ == Polyphony::sum ? sum : chosen);
}

void Engine::stop_all() {
  for (Voice& v : voices_) v.stop();
  limiter_.reset();
}

std::uint8_t Engine::active_voices() const {
  std::uint8_t count = 0;
  for (const Voice& v : voices_) count = static_cast<std::uint8_t>(count + (v.active() ? 1 : 0));
  return count;
}

}  // namespace hmp::synth
