// The container level of the SMF reader: RIFF RMID unwrapping, MThd, walking chunks to the end of the
// file. Events are parsed in smf_track.cpp, the Song is finished in smf_song.cpp.
#include "host/midi/smf_reader.hpp"

#include <algorithm>
#include <cstring>
#include <memory>
#include <string_view>

#include "host/common/error.hpp"
#include "host/common/input_file.hpp"
#include "host/midi/smf_detail.hpp"

namespace hmp::midi {
namespace {

using detail::place;

std::uint32_t be32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}
std::uint16_t be16(const std::uint8_t* p) { return static_cast<std::uint16_t>((p[0] << 8) | p[1]); }
std::uint32_t le32(const std::uint8_t* p) {  // RIFF sizes are little-endian
  return (std::uint32_t{p[3]} << 24) | (std::uint32_t{p[2]} << 16) | (std::uint32_t{p[1]} << 8) | p[0];
}

bool is_id(std::span<const std::uint8_t> bytes, std::size_t at, const char* id) {
  return bytes.size() >= at + 4 && std::memcmp(bytes.data() + at, id, 4) == 0;
}

// A chunk id of printable ASCII (a real chunk); anything else means we are not at a chunk boundary.
bool printable_id(const std::uint8_t* p) {
  return std::all_of(p, p + 4, [](std::uint8_t b) { return b >= 0x20 && b <= 0x7E; });
}

std::string id_text(const std::uint8_t* p) { return std::string(reinterpret_cast<const char*>(p), 4); }

std::size_t find_id(std::span<const std::uint8_t> bytes, std::size_t from, std::size_t to, const char* id) {
  const std::string_view hay(reinterpret_cast<const char*>(bytes.data()) + from, to - from);
  const std::size_t at = hay.find(std::string_view(id, 4));
  return at == std::string_view::npos ? std::string_view::npos : from + at;
}

[[noreturn]] void fail(std::int64_t chunk, std::uint64_t offset, const std::string& what) {
  throw BadInput(place(chunk, offset) + ": " + what);
}

// The byte range of the SMF: the whole file, or the `data` chunk of a RIFF RMID file.
struct Range {
  std::size_t begin = 0;
  std::size_t end = 0;
};

Range unwrap_riff(std::span<const std::uint8_t> bytes, detail::WarningLog& warnings) {
  if (bytes.size() < 12) fail(-1, 0, "RIFF header cut short");
  if (!is_id(bytes, 8, "RMID")) fail(-1, 8, "not a MIDI file: RIFF form \"" + id_text(bytes.data() + 8) + "\"");
  // The RIFF size field is not trusted: sub-chunks are looked for up to the end of the file.
  std::size_t pos = 12;
  while (pos + 8 <= bytes.size()) {
    const std::uint64_t size = le32(bytes.data() + pos + 4);
    const std::size_t body = pos + 8;
    if (is_id(bytes, pos, "data")) {
      std::size_t end = body + size;
      if (body + size > bytes.size()) {
        warnings.add(-1, pos, "RMID data chunk runs past the end of the file");
        end = bytes.size();
      }
      return Range{body, end};
    }
    pos = static_cast<std::size_t>(std::min<std::uint64_t>(bytes.size(), body + size + (size & 1)));  // word aligned
  }
  fail(-1, 12, "RIFF RMID file without a data chunk");
}

class SmfReader {
 public:
  explicit SmfReader(std::span<const std::uint8_t> bytes) : bytes_(bytes), state_(bytes.size()) {}

  ReadResult read() {
    if (bytes_.empty()) throw BadInput("empty file (0 bytes)");
    if (bytes_.size() > kMaxFileBytes) throw BadInput("file too large for a MIDI file");
    Range r{0, bytes_.size()};
    if (is_id(bytes_, 0, "RIFF")) r = unwrap_riff(bytes_, state_.warnings);
    const std::size_t body = read_header(r);
    walk_chunks(body, r.end);
    if (chunks_ == 0) fail(-1, body, "no track (MTrk chunk) in the file");
    if (chunks_ != announced_tracks_) {
      state_.warnings.add(-1, header_at_ + 10,
                          "the header announces " + std::to_string(announced_tracks_) + " tracks, the file has " +
                              std::to_string(chunks_));
    }
    if (state_.notes.empty() && state_.first_error) throw BadInput(*state_.first_error);
    ReadResult result;
    result.song.format = format_;
    result.song.division = division_;
    detail::finish_song(state_, result.song);
    result.warnings = state_.warnings.take();
    return result;
  }

 private:
  // MThd: returns where the chunks after it begin.
  std::size_t read_header(Range r) {
    std::size_t at = r.begin;
    if (!is_id(bytes_, at, "MThd")) {
      // Tolerate a short prefix (e.g. a MacBinary header) before MThd.
      const std::size_t look = std::min(r.end, r.begin + 256 + 4);
      at = find_id(bytes_, r.begin, look, "MThd");
      if (at == std::string_view::npos) fail(-1, r.begin, "not a MIDI file: no MThd header");
      state_.warnings.add(-1, r.begin, std::to_string(at - r.begin) + " bytes before the MThd header skipped");
    }
    header_at_ = at;
    if (r.end - at < 14) fail(-1, at, "MThd header cut short");
    std::uint64_t length = be32(bytes_.data() + at + 4);
    if (length < 6) {
      state_.warnings.add(-1, at + 4, "MThd length " + std::to_string(length) + " is less than 6; read as 6");
      length = 6;
    } else if (length > r.end - at - 8) {
      state_.warnings.add(-1, at + 4, "MThd length " + std::to_string(length) + " runs past the end; read as 6");
      length = 6;
    }
    format_ = be16(bytes_.data() + at + 8);
    announced_tracks_ = be16(bytes_.data() + at + 10);
    division_ = Division::from_field(be16(bytes_.data() + at + 12));
    if (format_ > 2) {
      state_.warnings.add(-1, at + 8, "unknown format " + std::to_string(format_) + "; read as format 1");
      format_ = 1;
    }
    if (!division_.smpte && division_.ticks_per_quarter == 0) {
      state_.warnings.add(-1, at + 12, "division of 0 ticks per quarter note; read as 96");
      division_.ticks_per_quarter = 96;
    }
    if (division_.smpte && division_.fps != 24 && division_.fps != 25 && division_.fps != 29 && division_.fps != 30) {
      // SMPTE time code has 24, 25, 29.97 (drop-frame, coded −29) and 30 frames a second.
      state_.warnings.add(-1, at + 12,
                          "SMPTE division of " + std::to_string(division_.fps) +
                              " frames a second (not 24, 25, 29.97 or 30); read as given");
    }
    if (division_.smpte && division_.ticks_per_frame == 0) {
      state_.warnings.add(-1, at + 12, "SMPTE division with 0 ticks per frame; read as 1");
      division_.ticks_per_frame = 1;
    }
    return at + 8 + static_cast<std::size_t>(length);
  }

  void walk_chunks(std::size_t pos, std::size_t end) {
    while (end - pos >= 8) {
      const std::uint8_t* head = bytes_.data() + pos;
      const std::uint64_t length = be32(head + 4);
      if (std::memcmp(head, "MTrk", 4) == 0) {
        pos = read_track(pos, length, end);
      } else if (printable_id(head)) {
        state_.warnings.add(-1, pos,
                            "unknown chunk \"" + id_text(head) + "\" (" + std::to_string(length) + " bytes) skipped");
        if (length > end - pos - 8) return;  // nothing after it
        pos += 8 + static_cast<std::size_t>(length);
      } else {
        // Not a chunk header (a track's length was wrong, or junk): resume at the next MTrk, if any.
        const std::size_t next = find_id(bytes_, pos, end, "MTrk");
        if (next == std::string_view::npos) {
          state_.warnings.add(-1, pos, std::to_string(end - pos) + " bytes that are not a chunk ignored");
          return;
        }
        state_.warnings.add(-1, pos, std::to_string(next - pos) + " bytes that are not a chunk skipped");
        pos = next;
      }
    }
    if (end > pos) state_.warnings.add(-1, pos, std::to_string(end - pos) + " trailing bytes ignored");
  }

  std::size_t read_track(std::size_t pos, std::uint64_t length, std::size_t end) {
    const auto chunk = static_cast<std::uint32_t>(chunks_++);
    detail::ChunkInput in;
    in.chunk = chunk;
    in.begin = pos + 8;
    in.end = in.begin + static_cast<std::size_t>(std::min<std::uint64_t>(length, end - in.begin));
    if (length > end - in.begin) {
      in.cut_by_eof = true;
      state_.warnings.add(chunk, pos + 4,
                          "declared length " + std::to_string(length) + " runs past the end of the file (" +
                              std::to_string(end - in.begin) + " bytes left)");
    }
    if (format_ == 0 && chunk == 1) {
      state_.warnings.add(chunk, pos, "format 0 file with more than one track chunk; all are read");
    }
    in.split_by_channel = format_ == 0;
    if (format_ == 2) {
      // Patterns play one after another, each with its own tempo map starting at the default tempo.
      in.tick_offset = pattern_end_;
      if (chunk > 0) state_.tempos.push_back(TempoMap::Point{pattern_end_, kDefaultTempo});
    }
    const detail::ChunkResult r = detail::parse_track(bytes_, in, state_);
    if (format_ == 2) pattern_end_ = r.end_tick;
    if (r.end_of_track && r.stop < in.end) {
      // A declared length longer than the track: if the next chunk starts right after End-of-Track,
      // resume there rather than inside it.
      if (end - r.stop >= 8 && is_id(bytes_, r.stop, "MTrk")) {
        state_.warnings.add(chunk, pos + 4,
                            "declared length " + std::to_string(length) +
                                " is longer than the track; the next chunk follows its End-of-Track");
        return r.stop;
      }
      state_.warnings.add(chunk, r.stop, std::to_string(in.end - r.stop) + " bytes after End-of-Track ignored");
    }
    return in.end;
  }

  std::span<const std::uint8_t> bytes_;
  detail::ParseState state_;
  std::size_t header_at_ = 0;
  std::uint16_t format_ = 1;
  std::uint16_t announced_tracks_ = 0;
  Division division_;
  std::size_t chunks_ = 0;
  std::uint64_t pattern_end_ = 0;
};

}  // namespace

detail::ParseState::ParseState(std::size_t file_size) {
  // A note needs at least 3 bytes (delta, key, velocity under running status), so up to a few million
  // notes this never grows (no copy, no doubling); pages that are never written cost no memory.
  constexpr std::size_t kReserveCap = std::size_t{1} << 22;
  notes.reserve(std::min(file_size / 3 + 1, kReserveCap));
}

ReadResult read_smf(std::span<const std::uint8_t> bytes) { return SmfReader(bytes).read(); }

ReadResult load_song(const std::filesystem::path& path) {
  // One open, fstat and read into a buffer that is not zero-filled first: on a small song the reading is
  // a good part of `hmp info`'s own time (docs/performance.md, MIDI parsing). InputFile refuses what is
  // not a regular file (a directory, a FIFO) with the same message as every other file the user names.
  const InputFile file(path.string());
  if (file.size() > kMaxFileBytes) throw BadInput(file.shown() + ": too large for a MIDI file");
  const auto length = static_cast<std::size_t>(file.size());
  const auto buffer = std::make_unique_for_overwrite<std::uint8_t[]>(length);
  file.read_all(buffer.get());
  const std::span<const std::uint8_t> bytes(buffer.get(), length);
  try {
    return read_smf(bytes);
  } catch (const BadInput& e) {
    // Name the file: the reader's own message only knows the track and byte offset.
    throw BadInput(file.shown() + ": " + e.what());
  }
}

}  // namespace hmp::midi
