#include "host/live/live_sound.hpp"

namespace hmp::live {

LiveSound::LiveSound(int channel, std::optional<std::uint8_t> program) : channel_(channel), fixed_program_(program) {
  program_.fill(program.value_or(0));
}

std::optional<audio::AudioEvent> LiveSound::on_message(const ChannelMessage& m) {
  const std::uint8_t ch = m.channel();
  if (channel_ >= 0 && ch != channel_) return std::nullopt;
  using Kind = audio::AudioEvent::Kind;
  using Control = midi::Control::Kind;
  audio::AudioEvent e;
  e.channel = ch;
  switch (m.kind()) {
    case 0x90:
      if (m.data2 != 0) {
        e.kind = Kind::note_on, e.key = m.data1, e.velocity = m.data2, e.program = program_[ch];
        return e;
      }
      [[fallthrough]];  // velocity 0: a note-off
    case 0x80: e.kind = Kind::note_off, e.key = m.data1; return e;
    case 0xB0: e.kind = Kind::control, e.control = Control::controller, e.key = m.data1, e.value = m.data2; return e;
    case 0xC0:
      if (!fixed_program_) program_[ch] = m.data1;  // the next note-on carries it
      return std::nullopt;
    case 0xD0: e.kind = Kind::control, e.control = Control::pressure, e.value = m.data1; return e;
    case 0xE0:
      e.kind = Kind::control, e.control = Control::pitch_bend;
      e.value = static_cast<std::uint16_t>(m.data1 | m.data2 << 7);
      return e;
    default: return std::nullopt;  // polyphonic aftertouch: FluidSynth's song path ignores it too
  }
}

}  // namespace hmp::live
