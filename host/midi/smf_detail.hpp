#pragma once
// Internals of the SMF reader shared by its .cpp files (not an API): the state one read builds up while
// walking the track chunks, the per-chunk event parser and the final pass that turns it into a Song.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "host/midi/song.hpp"

namespace hmp::midi::detail {

// "track 2 at byte 0x1a3f" (chunk ≥ 0) or "byte 0x1a3f".
std::string place(std::int64_t chunk, std::uint64_t offset);

// Warnings of one read. Each track reports a kind of problem once (with a count), so the list stays short;
// past kMaxWarnings the rest are only counted.
class WarningLog {
 public:
  static constexpr std::size_t kMaxWarnings = 200;
  void add(std::int64_t chunk, std::uint64_t offset, std::string_view text);
  std::vector<Warning> take();

 private:
  std::vector<Warning> list_;
  std::size_t suppressed_ = 0;
};

struct ProgramChange {
  std::uint64_t tick = 0;
  std::uint8_t channel = 0;
  std::uint8_t program = 0;
};

struct ParseState {
  explicit ParseState(std::size_t file_size);

  std::vector<Note> notes;  // end_tick == kPending (and end_us = FIFO link) while a note sounds
  std::vector<Track> tracks;
  std::vector<ProgramChange> program_changes;  // file order
  std::vector<TempoMap::Point> tempos;         // file order (format 2: patterns offset, resets added)
  std::vector<TimeSignature> time_signatures;  // file order
  WarningLog warnings;
  std::optional<std::string> first_error;      // "track N at byte X: …" of the first error in a track

  // FIFO of sounding notes per (channel, key) of the chunk being parsed: indices into notes, linked
  // through Note::end_us. A slot is valid only when its generation is the current chunk's.
  struct Slot {
    std::uint32_t generation = 0;
    std::uint32_t head = 0;
    std::uint32_t tail = 0;
  };
  std::vector<Slot> slots;  // 16 × 128
  std::uint32_t generation = 0;
};

inline constexpr std::uint64_t kPending = ~std::uint64_t{0};

// One MTrk chunk: its data is file[begin, end) (already clamped to the file).
struct ChunkInput {
  std::size_t begin = 0;
  std::size_t end = 0;
  std::uint32_t chunk = 0;
  std::uint64_t tick_offset = 0;    // format 2: where this pattern starts
  bool split_by_channel = false;    // format 0
  bool cut_by_eof = false;          // the declared length ran past the end of the file
};

struct ChunkResult {
  std::uint64_t end_tick = 0;     // absolute: End-of-Track, or the last complete event
  std::size_t stop = 0;           // file offset where reading stopped (just after End-of-Track if seen)
  bool end_of_track = false;
};

// Parses the chunk's events, appends its notes, tracks, program/tempo/time-signature events and warnings.
ChunkResult parse_track(std::span<const std::uint8_t> file, const ChunkInput& in, ParseState& state);

// Tempo map, note times and programs, per-track statistics.
void finish_song(ParseState& state, Song& song);

// Valid UTF-8 of a text meta event: UTF-8 kept, other bytes read as Latin-1, trailing NULs and
// whitespace dropped (leading spaces too), control characters replaced by spaces.
std::string text_to_utf8(std::span<const std::uint8_t> text);

}  // namespace hmp::midi::detail
