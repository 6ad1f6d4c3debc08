#pragma once
// What `hmp live` plays through FluidSynth for the messages it feels (unless --no-audio): each note-on,
// note-off, controller (the sustain pedal, volume, all notes off…), pitch bend and channel pressure of
// the chosen channel(s), as an audio event to apply at once. The program is the chosen instrument on
// every channel, or, without one, what the input's program changes say (GM program 1, the piano, until
// then); channel 10 plays the drum kit, as in a song.
#include <array>
#include <cstdint>
#include <optional>

#include "host/audio/audio_events.hpp"
#include "host/live/midi_stream.hpp"

namespace hmp::live {

class LiveSound {
 public:
  // channel: 0–15, or −1 for every channel (as MapperOptions); program: the instrument, or nullopt.
  LiveSound(int channel, std::optional<std::uint8_t> program);
  std::optional<audio::AudioEvent> on_message(const ChannelMessage& m);

 private:
  int channel_;
  std::optional<std::uint8_t> fixed_program_;
  std::array<std::uint8_t, 16> program_{};
};

}  // namespace hmp::live
