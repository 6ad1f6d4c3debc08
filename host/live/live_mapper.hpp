#pragma once
// Live MIDI input → the device's Live events (docs/protocol.md, Live): what `hmp live` sends for each
// message of the chosen channel(s), at once.
//
//  - note-on starts a held note now, note-off (or note-on at velocity 0) releases it;
//  - the sustain pedal (CC64 ≥ 64) holds released notes until it lifts, as `--pedal` does for songs;
//    CC121 (reset all controllers) lifts it and centres the bend; CC120 and CC123 release every note;
//  - pitch bend moves every sounding note of the channel, `bend_semitones` at full deflection, along the
//    key → frequency mapping (interpolated between neighbouring keys, in log frequency);
//  - velocity scales the mapped amplitude (velocity / 127);
//  - the key → frequency and amplitude mapping (design §5) is that of a track whose keys are every key of
//    the range: a song's range is not known before it is played. Keys outside the range map as its ends.
// A MIDI channel is the device track (0–15); the key is the MIDI key.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "host/live/midi_stream.hpp"
#include "shared/mapping/mapping.hpp"
#include "shared/protocol/protocol.hpp"

namespace hmp::live {

struct KeyRange {
  int low = 21, high = 108;  // the piano's A0–C8
};
// "LOW:HIGH", each a key number 0–127 or a note name (C4 = 60, sharps as C#4, flats as Db4); throws
// BadInput naming the text when it is not one, or LOW > HIGH.
KeyRange parse_key_range(const std::string& text);
std::string to_string(const KeyRange& range);  // "21:108 (A0–C8)"

struct MapperOptions {
  int channel = -1;  // 0–15; −1: every channel
  KeyRange keys;
  mapping::Mode mode = mapping::Mode::paper;
  mapping::Ranges ranges;
  std::uint8_t preset = static_cast<std::uint8_t>(envelope::Preset::harpsichord);
  double bend_semitones = 2.0;  // the GM default pitch-bend sensitivity
};

struct DeviceEvent {
  std::uint8_t track = 0;  // the MIDI channel
  protocol::LiveEvent event;
};

struct MapperCounts {
  std::uint64_t notes_on = 0, notes_off = 0, bends = 0;
  std::uint64_t other_channels = 0;  // messages of a channel not chosen
};

class LiveMapper {
 public:
  explicit LiveMapper(const MapperOptions& options);
  // Appends the device events one message calls for (none, one, or one per sounding note).
  void on_message(const ChannelMessage& m, std::vector<DeviceEvent>& out);
  // A bent key's frequency: `key` plus `semitones` (fractional) along the mapping.
  double frequency_hz(double key) const;
  const MapperCounts& counts() const { return counts_; }

 private:
  struct Channel {
    std::array<bool, 128> down{};      // the key is held on the keyboard
    std::array<bool, 128> sounding{};  // a held note on the device (down, or kept by the pedal)
    bool pedal = false;
    int bend = 0;  // −8192 … 8191
  };
  void release(std::uint8_t channel, std::uint8_t key, std::vector<DeviceEvent>& out);
  void release_all(std::uint8_t channel, std::vector<DeviceEvent>& out);
  void lift_pedal(std::uint8_t channel, std::vector<DeviceEvent>& out);
  double bent_key(const Channel& c, std::uint8_t key) const;

  MapperOptions options_;
  mapping::Mapper mapper_;
  std::array<Channel, 16> channels_{};
  MapperCounts counts_;
};

}  // namespace hmp::live
