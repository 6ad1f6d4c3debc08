#pragma once
// Internals of the SMF reader shared by its .cpp files (not an API): the state one read builds up while
// walking the track chunks, the per-chunk event parser and the final pass that turns it into a Song.
#include <algorithm>
#include <cstdint>
#include <memory>
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

  std::vector<Note> notes;  // end_tick is a sounding link (below) until the note ends
  std::vector<Track> tracks;
  std::vector<ProgramChange> program_changes;  // file order
  std::vector<Control> controls;               // file order (sorted by tick at the end)
  std::vector<TempoMap::Point> tempos;         // file order (format 2: patterns offset, resets added)
  std::vector<TimeSignature> time_signatures;  // file order
  WarningLog warnings;
  std::optional<std::string> first_error;  // "track N at byte X: …" of the first error in a track

  // FIFO of sounding notes per (channel, key) of the chunk being parsed: indices into notes, linked
  // through Note::end_tick (sounding_link). A slot is valid only when its generation is the current chunk's.
  struct Slot {
    std::uint32_t generation;
    std::uint32_t head;
    std::uint32_t tail;
  };
  // The table is 24 KiB; a song uses a few channels, so a channel's 128 slots are cleared on its first
  // note only (fewer pages touched: each first touch is a page fault, ~1 µs of a ~0.6 ms `hmp info`).
  Slot& slot(std::uint8_t channel, std::uint8_t key) {
    if ((cleared_channels & (1u << channel)) == 0) {
      std::fill_n(slots.get() + channel * 128u, 128, Slot{0, 0, 0});
      cleared_channels = static_cast<std::uint16_t>(cleared_channels | (1u << channel));
    }
    return slots[channel * 128u + key];
  }
  std::unique_ptr<Slot[]> slots = std::make_unique_for_overwrite<Slot[]>(16 * 128);
  std::uint16_t cleared_channels = 0;
  std::uint32_t generation = 0;  // of the chunk being parsed; 0 is no chunk's
};

// While a note sounds its end_tick is not a tick but a link: kSounding | index of the next sounding note
// of the same (channel, key) in notes, or kSounding | kNoNext for the last one. This keeps the FIFO
// inside the notes themselves (no allocation per event, no extra field). Bit 63 cannot be a real tick:
// a tick is the sum of the delta times read before it (format 2 patterns continue from the previous
// pattern's end, they do not add to it); each delta is < 2^28 (a VLQ of at most 4 bytes) and takes at
// least one byte, so a tick is < 2^28 × the input size, and read_smf refuses inputs over kMaxFileBytes
// (2^28): ticks stay below 2^56.
inline constexpr std::uint64_t kSounding = std::uint64_t{1} << 63;
inline constexpr std::uint32_t kNoNext = 0xFFFFFFFFu;
inline constexpr std::uint64_t sounding_link(std::uint32_t next) { return kSounding | next; }
inline constexpr bool is_sounding(std::uint64_t end_tick) { return (end_tick & kSounding) != 0; }
inline constexpr std::uint32_t next_sounding(std::uint64_t link) { return static_cast<std::uint32_t>(link); }

// One MTrk chunk: its data is file[begin, end) (already clamped to the file).
struct ChunkInput {
  std::size_t begin = 0;
  std::size_t end = 0;
  std::uint32_t chunk = 0;
  std::uint64_t tick_offset = 0;  // format 2: where this pattern starts
  bool split_by_channel = false;  // format 0
  bool cut_by_eof = false;        // the declared length ran past the end of the file
};

struct ChunkResult {
  std::uint64_t end_tick = 0;  // absolute: End-of-Track, or the last complete event
  std::size_t stop = 0;        // file offset where reading stopped (just after End-of-Track if seen)
  bool end_of_track = false;
};

// Parses the chunk's events, appends its notes, tracks, program/tempo/time-signature events and warnings.
ChunkResult parse_track(std::span<const std::uint8_t> file, const ChunkInput& in, ParseState& state);

// Tempo map, note programs, per-track statistics.
void finish_song(ParseState& state, Song& song);

// Valid UTF-8 of a text meta event: UTF-8 kept, other bytes read as Latin-1, trailing NULs and
// whitespace dropped (leading spaces too), control characters replaced by spaces.
std::string text_to_utf8(std::span<const std::uint8_t> text);

}  // namespace hmp::midi::detail
