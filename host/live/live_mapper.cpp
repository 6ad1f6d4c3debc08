#include "host/live/live_mapper.hpp"

#include <algorithm>
#include <cmath>

#include "host/common/error.hpp"
#include "host/midi/key_name.hpp"
#include "shared/synth/frequency.hpp"

namespace hmp::live {
namespace {

constexpr std::uint8_t kNoteOff = 0x80, kNoteOn = 0x90, kControl = 0xB0, kPitchBend = 0xE0;
constexpr std::uint8_t kSustain = 64, kAllSoundOff = 120, kResetControllers = 121, kAllNotesOff = 123;

mapping::KeySet keys_of(const KeyRange& range) {
  mapping::KeySet keys;
  for (int k = range.low; k <= range.high; ++k) keys.add(static_cast<std::uint8_t>(k));
  return keys;
}

}  // namespace

KeyRange parse_key_range(const std::string& text) {
  const std::size_t colon = text.find(':');
  const auto bad = [&](const char* why) { return BadInput("--key-range '" + text + "': " + why); };
  if (colon == std::string::npos) throw bad("expected LOW:HIGH, e.g. 21:108 or A0:C8");
  const std::optional<int> low = midi::parse_key(std::string_view(text).substr(0, colon));
  const std::optional<int> high = midi::parse_key(std::string_view(text).substr(colon + 1));
  if (!low || !high) throw bad("each end is a key 0–127 or a note name from C-1 to G9 (C4 = 60)");
  if (*low > *high) throw bad("the low key is above the high one");
  return {*low, *high};
}

std::string to_string(const KeyRange& range) {
  return std::to_string(range.low) + ":" + std::to_string(range.high) + " (" + midi::key_name(range.low) + "–" +
         midi::key_name(range.high) + ")";
}

LiveMapper::LiveMapper(const MapperOptions& options)
    : options_(options), mapper_(options.mode, options.ranges, keys_of(options.keys)) {}

double LiveMapper::frequency_hz(double key) const {
  const double k = std::clamp(key, 0.0, 127.0);
  const auto below = static_cast<int>(std::floor(k));
  const int above = std::min(below + 1, 127);
  const double f0 = mapper_.map(static_cast<std::uint8_t>(below)).freq_hz;
  const double f1 = mapper_.map(static_cast<std::uint8_t>(above)).freq_hz;
  const double t = k - below;
  return f0 > 0 && f1 > 0 ? std::exp(std::log(f0) + t * (std::log(f1) - std::log(f0))) : f0;
}

double LiveMapper::bent_key(const Channel& c, std::uint8_t key) const {
  return key + options_.bend_semitones * c.bend / 8192.0;
}

void LiveMapper::on_message(const ChannelMessage& m, std::vector<DeviceEvent>& out) {
  const std::uint8_t ch = m.channel();
  if (options_.channel >= 0 && ch != options_.channel) {
    ++counts_.other_channels;
    return;
  }
  Channel& c = channels_[ch];
  const std::uint8_t key = m.data1;
  const auto emit = [&](protocol::LiveEvent e) { out.push_back({ch, e}); };
  switch (m.kind()) {
    case kNoteOn:
      if (m.data2 != 0) {
        const mapping::Haptic h = mapper_.map(key);
        const double amplitude = h.amplitude * m.data2 / 127.0;
        emit({protocol::LiveOp::on, key, options_.preset, synth::freq_to_q20(frequency_hz(bent_key(c, key))),
              synth::amp_to_q16(amplitude)});
        c.down[key] = c.sounding[key] = true;
        ++counts_.notes_on;
        return;
      }
      [[fallthrough]];  // velocity 0: a note-off
    case kNoteOff:
      c.down[key] = false;
      if (!c.pedal) release(ch, key, out);
      return;
    case kControl:
      if (m.data1 == kSustain) {
        const bool down = m.data2 >= 64;
        if (c.pedal && !down) lift_pedal(ch, out);
        c.pedal = down;
      } else if (m.data1 == kResetControllers) {
        if (c.pedal) lift_pedal(ch, out);
        c.pedal = false;
        c.bend = 0;
      } else if (m.data1 == kAllSoundOff || m.data1 == kAllNotesOff) {
        release_all(ch, out);
      }
      return;
    case kPitchBend: {
      c.bend = (m.data1 | m.data2 << 7) - 8192;
      for (int k = 0; k < 128; ++k) {
        if (!c.sounding[static_cast<std::size_t>(k)]) continue;
        const auto u = static_cast<std::uint8_t>(k);
        emit({protocol::LiveOp::bend, u, 0, synth::freq_to_q20(frequency_hz(bent_key(c, u))), 0});
        ++counts_.bends;
      }
      return;
    }
    default: return;  // aftertouch, program change, channel pressure: not felt
  }
}

void LiveMapper::release(std::uint8_t channel, std::uint8_t key, std::vector<DeviceEvent>& out) {
  Channel& c = channels_[channel];
  if (!c.sounding[key]) return;
  c.sounding[key] = false;
  out.push_back({channel, {protocol::LiveOp::off, key, 0, 0, 0}});
  ++counts_.notes_off;
}

void LiveMapper::release_all(std::uint8_t channel, std::vector<DeviceEvent>& out) {
  Channel& c = channels_[channel];
  for (int k = 0; k < 128; ++k) {
    c.down[static_cast<std::size_t>(k)] = false;
    release(channel, static_cast<std::uint8_t>(k), out);
  }
}

// The notes the pedal kept: every sounding key no longer held down.
void LiveMapper::lift_pedal(std::uint8_t channel, std::vector<DeviceEvent>& out) {
  Channel& c = channels_[channel];
  for (int k = 0; k < 128; ++k)
    if (!c.down[static_cast<std::size_t>(k)]) release(channel, static_cast<std::uint8_t>(k), out);
}

}  // namespace hmp::live
