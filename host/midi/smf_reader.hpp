#pragma once
// Standard MIDI File reader (design §4): lenient, never crashes or hangs, memory bounded by the file size.
//
// Decisions where design §4 leaves room (all reported as warnings unless noted):
// - Container: an optional RIFF RMID wrapper is unwrapped (the SMF is its `data` chunk); MThd must come
//   first (up to 256 junk bytes before it, e.g. a MacBinary header, are skipped). MThd longer than 6 is
//   honoured, shorter is read as 6. Then every chunk to the end of the file is read whatever ntrks says:
//   MTrk chunks are tracks, other chunks are skipped; bytes that are not a chunk header make the reader
//   look for the next "MTrk"; fewer than 8 trailing bytes are ignored.
// - An error inside a track (a data byte without running status, a status byte F1–FE, a status byte
//   where a data byte belongs, a VLQ of 5+ bytes) ends that track there: what was read before is kept
//   and the error becomes a warning. Only when the whole file then has no note at all does read_smf throw,
//   with the first error's message (a song with nothing to play from a broken file is bad input).
// - Truncation (the file ends inside a track or inside an event) keeps the events before it.
// - Note pairing is first-in-first-out per (track chunk, channel, key) in file order. At one tick an
//   older sounding note is always ended before a newer one, which is what "note-offs before note-ons"
//   asks for; a note-on followed by its note-off at the same tick gives a zero-length note, which is kept
//   (music21's test16 writes one on purpose). Note-offs with nothing to end are ignored (counted).
// - Programs: a note's program is that of the latest program change on its channel, in any track, at a
//   tick ≤ the note's start (one at the same tick applies to it; of several at one tick the last in file
//   order wins). Format 2 patterns play in sequence, so program changes carry over from one to the next.
// - Format 0 files with several MTrk chunks (invalid) are read chunk by chunk, each split by channel,
//   all playing together. Unknown formats (> 2) are read as format 1.
// - Division 0 ticks per quarter is read as 96, SMPTE 0 ticks per frame as 1.
// - Places in messages: "track N" is the MTrk chunk (0-based, file order; for format 0 one chunk may be
//   several logical tracks), "byte 0x…" the offset in the bytes given (a RIFF header included).
// - Names are made valid UTF-8: bytes that are not UTF-8 are read as Latin-1; trailing NULs/spaces dropped.
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "host/midi/song.hpp"

namespace hmp::midi {

struct ReadResult {
  Song song;
  std::vector<Warning> warnings;
};

// Throws hmp::BadInput with a one-line message naming the place, e.g. "track 2 at byte 0x1a3f: data byte
// without running status", or "not a MIDI file: no MThd header at byte 0x0".
ReadResult read_smf(std::span<const std::uint8_t> bytes);

// Reads the file and parses it. I/O problems throw hmp::BadInput naming the path.
// Files larger than kMaxFileBytes are refused (no MIDI file is that big; memory stays bounded).
inline constexpr std::uintmax_t kMaxFileBytes = 256u << 20;
ReadResult load_song(const std::filesystem::path& path);

}  // namespace hmp::midi
