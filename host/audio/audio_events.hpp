#pragma once
// The song's audio as a time-ordered list of channel events for the synthesizer (design §14): note-on /
// note-off with velocity, each note-on carrying the GM program its channel had at that moment in the
// file (the synthesizer switches the channel's program just before the note when it differs), and the
// song's controls (design §17): the sound's controllers (sustain, volume, expression, pan, sends, RPN 0
// pitch bend range, …), pitch bend, channel pressure and program changes, on the same clock.
#include <cstdint>
#include <vector>

#include "host/midi/song.hpp"

namespace hmp::audio {

struct AudioEvent {
  // At equal times: note-offs, then controls (a pedal or volume set with a note applies to it), then
  // note-ons.
  enum class Kind : std::uint8_t { note_off = 0, control = 1, note_on = 2 };
  std::int64_t time_us = 0;  // song time
  Kind kind = Kind::note_on;
  std::uint8_t channel = 0;   // 0–15 (9: GM drums)
  std::uint8_t key = 0;       // 0–127
  std::uint8_t velocity = 0;  // note_on: 1–127
  std::uint8_t program = 0;   // note_on: GM program 0–127 (drum kit on channel 9)
  // control: what kind, the controller (or program) number in `key`, its value here.
  midi::Control::Kind control = midi::Control::Kind::controller;
  std::uint16_t value = 0;
  friend bool operator==(const AudioEvent&, const AudioEvent&) = default;
};

// All notes, sorted by time, note-offs before note-ons at equal times. Overlapping notes of the same
// key and channel sound until the last of them ends (one note-off, then), as a synthesizer releases
// every voice of a key on a note-off. A zero-length note gets its note-off 1 µs after its note-on (the
// synthesizer's minimum note length keeps it audible).
// With the song's controls.
std::vector<AudioEvent> audio_events(const midi::Song& song);
// The same for any notes (and controls), their ticks turned into song time by `tempo_map`.
std::vector<AudioEvent> audio_events(const std::vector<midi::Note>& notes, const midi::TempoMap& tempo_map,
                                     const std::vector<midi::Control>& controls = {});

}  // namespace hmp::audio
