#include "host/audio/audio_events.hpp"

#include <algorithm>
#include <array>

namespace hmp::audio {

std::vector<AudioEvent> audio_events(const midi::Song& song) {
  return audio_events(song.notes, song.tempo_map, song.controls);
}

std::vector<AudioEvent> audio_events(const std::vector<midi::Note>& notes, const midi::TempoMap& tempo_map,
                                     const std::vector<midi::Control>& controls) {
  using Kind = AudioEvent::Kind;
  std::vector<AudioEvent> raw;
  raw.reserve(notes.size() * 2 + controls.size());
  std::size_t control_hint = 0;
  for (const midi::Control& c : controls) {
    AudioEvent e{tempo_map.micros(c.tick, control_hint),
                 Kind::control,
                 static_cast<std::uint8_t>(c.channel & 0x0F),
                 c.number,
                 0,
                 0};
    e.control = c.kind;
    e.value = c.value;
    raw.push_back(e);
  }
  std::size_t start_hint = 0, end_hint = 0;  // notes come in start order per track: mostly increasing ticks
  for (const midi::Note& n : notes) {
    const std::int64_t start_us = tempo_map.micros(n.start_tick, start_hint);
    const std::int64_t end_us = tempo_map.micros(n.end_tick, end_hint);
    const auto ch = static_cast<std::uint8_t>(n.channel & 0x0F), key = static_cast<std::uint8_t>(n.key & 0x7F);
    const auto velocity = static_cast<std::uint8_t>(std::clamp<int>(n.velocity, 1, 127));
    const auto program = static_cast<std::uint8_t>(n.program & 0x7F);
    raw.push_back({start_us, Kind::note_on, ch, key, velocity, program});
    raw.push_back({std::max(end_us, start_us + 1), Kind::note_off, ch, key, 0, 0});
  }
  std::stable_sort(raw.begin(), raw.end(), [](const AudioEvent& a, const AudioEvent& b) {
    return a.time_us != b.time_us ? a.time_us < b.time_us : a.kind < b.kind;
  });

  std::vector<AudioEvent> out;
  out.reserve(raw.size());
  std::array<std::array<std::uint32_t, 128>, 16> held{};  // sounding notes per channel and key
  for (const AudioEvent& e : raw) {
    std::uint32_t& count = held[e.channel][e.key];
    if (e.kind == Kind::control) {
      out.push_back(e);
    } else if (e.kind == Kind::note_on) {
      ++count;
      out.push_back(e);
    } else if (--count == 0) {  // every note-off sorts after its own note-on (end > start): count ≥ 1
      out.push_back(e);
    }
  }
  return out;
}

}  // namespace hmp::audio
