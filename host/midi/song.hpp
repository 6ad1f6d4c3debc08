#pragma once
// The song model built from a Standard MIDI File (design §4): logical tracks, paired notes (in ticks; their
// times come from the tempo map), the global tempo map, and what the reader had to warn about.
//
// Logical tracks: format 1 → one per MTrk chunk (also the ones without notes, e.g. a conductor track);
// format 0 → each chunk split by channel, one logical track per channel in the order of the channel's
// first note (a chunk without notes still gives one empty track); format 2 → one per pattern, patterns
// sequenced one after another. Indices are 0-based in that order (what `--track T` means).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "host/midi/tempo_map.hpp"
#include "shared/mapping/mapping.hpp"

namespace hmp::midi {

inline constexpr std::uint8_t kDrumChannel = 9;  // MIDI channel 10, 0-based

// One paired note, in ticks only. 24 bytes: a 5 MB file can hold ~600k of them and they are most of a
// read's memory (the midi-parse benchmark allows 3 × the file size + 20 MiB of peak RSS), so times are not
// stored: Song::start_us() and friends compute them from the tempo map when asked.
struct Note {
  std::uint64_t start_tick = 0;  // absolute; format 2 patterns are offset to play one after another
  std::uint64_t end_tick = 0;    // ≥ start_tick; equal for a zero-length note (kept, see smf_reader.hpp)
  std::uint32_t track = 0;       // logical track index
  std::uint8_t channel = 0;      // 0–15 (9 = drums)
  std::uint8_t key = 0;          // 0–127
  std::uint8_t velocity = 0;     // 1–127 (velocity 0 is a note-off)
  std::uint8_t program = 0;      // the channel's GM program at the note's start (0 when never set)
};
static_assert(sizeof(Note) == 24, "Note must stay compact");

// A channel message other than a note (design §17): what the song's sound needs besides the
// notes. Controllers are per channel in MIDI: a track's controllers are those on its channels.
struct Control {
  enum class Kind : std::uint8_t { controller = 0xB, program = 0xC, pressure = 0xD, pitch_bend = 0xE };
  std::uint64_t tick = 0;
  Kind kind = Kind::controller;
  std::uint8_t channel = 0;
  std::uint8_t number = 0;  // controller number; program number for `program`
  std::uint16_t value = 0;  // 0–127; pitch bend 0–16383 (8192 = none)
};

// The controllers the song's sound follows (CC numbers): the rest are read and dropped.
inline constexpr std::uint8_t kSoundControllers[] = {
    0,   32,             // bank select (FluidSynth picks the bank with them)
    1,                   // modulation
    6,   38,  100, 101,  // data entry and RPN select (RPN 0: pitch bend range)
    7,   10,  11,        // volume, pan, expression
    64,  66,  67,        // sustain, sostenuto, soft pedals
    91,  93,             // reverb and chorus sends
    120, 121, 123};      // all sound off, reset all controllers, all notes off
bool is_sound_controller(std::uint8_t number);
// "sustain", "volume", …, "CC 20" for the others.
std::string controller_name(std::uint8_t number);

// A (channel, program) pair some notes of a track were played with.
struct ProgramUse {
  std::uint8_t channel = 0;
  std::uint8_t program = 0;
  std::uint32_t notes = 0;  // how many of the track's notes used it
};

struct Track {
  std::uint32_t index = 0;           // logical index
  std::uint32_t chunk = 0;           // the MTrk chunk it came from (0-based, file order; warnings use this)
  std::string name;                  // sequence/track name meta (or instrument name), valid UTF-8; may be empty
  std::uint16_t channels = 0;        // bit c set: the track has notes on channel c
  std::vector<ProgramUse> programs;  // in order of first use
  std::uint32_t note_count = 0;
  mapping::KeySet keys;        // the keys the track uses
  std::uint64_t end_tick = 0;  // End-of-Track (or last event read), absolute
  std::int64_t end_us = 0;

  bool has_channel(std::uint8_t c) const { return c < 16 && ((channels >> c) & 1u) != 0; }
  int distinct_keys() const { return keys.count(); }
  int key_min() const { return keys.min(); }  // −1 when the track has no notes
  int key_max() const { return keys.max(); }  // −1 when the track has no notes
  // The program and channel of the track's first note (what `hmp info` shows; `programs` has the rest).
  std::uint8_t program() const { return programs.empty() ? 0 : programs.front().program; }
  std::uint8_t channel() const { return programs.empty() ? 0 : programs.front().channel; }
  bool is_drums() const { return channels == (1u << kDrumChannel); }
};

struct TimeSignature {
  std::uint64_t tick = 0;
  std::int64_t us = 0;
  std::uint8_t numerator = 4;
  std::uint8_t denominator_log2 = 2;  // the denominator is 2^this (as stored in the file)
  std::uint8_t clocks_per_click = 24;
  std::uint8_t thirty_seconds_per_quarter = 8;
};

struct Warning {
  std::int64_t chunk = -1;   // MTrk chunk index, −1 for the file as a whole
  std::uint64_t offset = 0;  // byte offset in the file as given (RIFF header included)
  std::string message;       // one line, e.g. "track 2 at byte 0x1a3f: running status after a meta event"
};

struct Song {
  std::uint16_t format = 1;  // as in the header (unknown formats are read as format 1)
  Division division;
  std::vector<Track> tracks;
  std::vector<Note> notes;  // grouped by chunk, in start order within a chunk
  TempoMap tempo_map;
  std::vector<TempoChange> tempo_changes;  // the map's segments: [0] is the starting tempo at tick 0
  std::vector<TimeSignature> time_signatures;
  std::vector<Control> controls;  // by tick (file order at equal ticks): the sound's controllers,
                                  // pitch bends, channel pressure, program changes
  std::uint64_t end_tick = 0;     // the latest track end
  std::int64_t duration_us = 0;

  double duration_s() const { return static_cast<double>(duration_us) * 1e-6; }
  // A note's times from the tempo map: integer µs (rounded once, see tempo_map.hpp) and seconds.
  std::int64_t start_us(const Note& n) const { return tempo_map.micros(n.start_tick); }
  std::int64_t end_us(const Note& n) const { return tempo_map.micros(n.end_tick); }
  double start_s(const Note& n) const { return static_cast<double>(start_us(n)) * 1e-6; }
  double end_s(const Note& n) const { return static_cast<double>(end_us(n)) * 1e-6; }
  // The notes of one logical track, in start order (ties keep file order).
  std::vector<Note> track_notes(std::uint32_t track) const;
};

// What the song's controls do on the channels a track plays on (`hmp info`), in controller-number order:
// "sustain", "volume", "pan", … then "pitch bend", "channel pressure", and "program changes" when a
// channel changes to another program after its first; empty when none.
std::vector<std::string> controllers_used(const Song& song, std::uint32_t track);

// `--track T` (design §3): a 0-based index, or a case-insensitive part of a track's name or of its GM
// instrument name. Among several matches the first track with notes wins (then the first at all).
std::optional<std::uint32_t> find_track(const Song& song, std::string_view query);

}  // namespace hmp::midi
