// One MTrk chunk → notes, program/tempo/time-signature events and warnings (design §4). Single pass, no
// heap allocation per event: notes go into a vector reserved for the whole file, sounding notes are kept
// in per-(channel, key) FIFOs linked through the notes themselves.
#include <array>
#include <cstdio>

#include "host/midi/smf_detail.hpp"

namespace hmp::midi::detail {
namespace {

constexpr std::uint32_t kNone = 0xFFFFFFFFu;

// How often something happened in this chunk and where first: reported once per chunk.
struct Tally {
  std::uint64_t count = 0;
  std::size_t first = 0;
  void hit(std::size_t at) {
    if (count++ == 0) first = at;
  }
};

std::string times(const char* what, std::uint64_t count) {
  if (count == 1) return what;
  return std::string(what) + " (" + std::to_string(count) + " times)";
}

class TrackParser {
 public:
  TrackParser(std::span<const std::uint8_t> file, const ChunkInput& in, ParseState& state)
      : data_(file.data()),
        file_(file),
        in_(in),
        st_(state),
        p_(in.begin),
        end_(in.end),
        tick_(in.tick_offset),
        last_tick_(in.tick_offset),
        first_note_(state.notes.size()),
        base_track_(static_cast<std::uint32_t>(state.tracks.size())) {
    channel_track_.fill(kNone);
    ++st_.generation;  // forget the FIFOs of the previous chunk
  }

  ChunkResult run() {
    while (step()) {
    }
    const std::uint64_t end_tick = finish();
    return ChunkResult{end_tick, p_, saw_end_of_track_};
  }

 private:
  // Reads one event; false when the track is over (End-of-Track, end of data, truncation, error).
  bool step() {
    if (p_ >= end_) {
      missing_end_of_track();
      return false;
    }
    const std::size_t event_at = p_;
    std::uint32_t delta = 0;
    if (!read_vlq(delta, event_at)) return false;
    tick_ += delta;
    if (p_ >= end_) return truncated(event_at);
    std::uint8_t status = data_[p_];
    if (status < 0x80) {
      if (running_ == 0) return error(p_, "data byte without running status");
      if (after_meta_or_sysex_) {
        running_after_meta_.hit(p_);
        after_meta_or_sysex_ = false;
      }
      status = running_;
    } else if (status < 0xF0) {
      running_ = status;
      after_meta_or_sysex_ = false;
      ++p_;
    } else if (status == 0xFF) {
      ++p_;
      return meta(event_at);
    } else if (status == 0xF0 || status == 0xF7) {
      ++p_;
      return sysex(event_at);
    } else {
      char text[96];
      std::snprintf(text, sizeof text, "illegal status byte 0x%02x (a system message) inside a track",
                    static_cast<unsigned>(status));
      return error(p_, text);
    }
    return channel_message(status, event_at);
  }

  bool channel_message(std::uint8_t status, std::size_t event_at) {
    const std::size_t need = (status & 0xE0) == 0xC0 ? 1 : 2;  // Cx, Dx have one data byte
    if (end_ - p_ < need) return truncated(event_at);
    const std::uint8_t d1 = data_[p_];
    const std::uint8_t d2 = need == 2 ? data_[p_ + 1] : 0;
    if (d1 >= 0x80 || d2 >= 0x80) {
      const std::size_t at = d1 >= 0x80 ? p_ : p_ + 1;
      char text[80];
      std::snprintf(text, sizeof text, "status byte 0x%02x where a data byte belongs",
                    static_cast<unsigned>(data_[at]));
      return error(at, text);
    }
    const std::size_t data_at = p_;
    p_ += need;
    last_tick_ = tick_;
    const auto channel = static_cast<std::uint8_t>(status & 0x0F);
    switch (status >> 4) {
      case 0x9:
        if (d2 != 0) {
          note_on(channel, d1, d2);
        } else {
          note_off(channel, d1, data_at);
        }
        break;
      case 0x8: note_off(channel, d1, data_at); break;
      case 0xC:
        st_.program_changes.push_back(ProgramChange{tick_, channel, d1});
        st_.controls.push_back({tick_, Control::Kind::program, channel, d1, 0});
        break;
      case 0xB:
        if (is_sound_controller(d1)) st_.controls.push_back({tick_, Control::Kind::controller, channel, d1, d2});
        break;
      case 0xD: st_.controls.push_back({tick_, Control::Kind::pressure, channel, 0, d1}); break;
      case 0xE:
        st_.controls.push_back(
            {tick_, Control::Kind::pitch_bend, channel, 0, static_cast<std::uint16_t>(d1 | (d2 << 7))});
        break;
      default: break;
    }
    return true;
  }

  bool meta(std::size_t event_at) {
    if (p_ >= end_) return truncated(event_at);
    const std::uint8_t type = data_[p_++];
    std::uint32_t length = 0;
    if (!read_vlq(length, event_at)) return false;
    if (end_ - p_ < length) return truncated(event_at);
    const std::span<const std::uint8_t> body = file_.subspan(p_, length);
    p_ += length;
    last_tick_ = tick_;
    after_meta_or_sysex_ = true;
    switch (type) {
      case 0x2F:  // End-of-Track
        saw_end_of_track_ = true;
        return false;
      case 0x51:  // tempo: µs per quarter note, 24 bits
        if (length >= 3) {
          const std::uint32_t us = (std::uint32_t{body[0]} << 16) | (std::uint32_t{body[1]} << 8) | body[2];
          if (us != 0) {
            st_.tempos.push_back(TempoMap::Point{tick_, us});
            break;
          }
        }
        malformed_.hit(event_at);
        break;
      case 0x58:  // time signature nn dd cc bb
        if (length >= 4 && body[1] <= 7) {
          st_.time_signatures.push_back(TimeSignature{tick_, 0, body[0], body[1], body[2], body[3]});
        } else {
          malformed_.hit(event_at);
        }
        break;
      case 0x03:  // sequence/track name
        if (!has_name_) {
          name_ = text_to_utf8(body);
          has_name_ = !name_.empty();
        }
        break;
      case 0x04:  // instrument name: the name when there is no track name
        if (instrument_.empty()) instrument_ = text_to_utf8(body);
        break;
      default: break;
    }
    return true;
  }

  // F0 len data / F7 len data: skipped whole, never parsed as events.
  bool sysex(std::size_t event_at) {
    std::uint32_t length = 0;
    if (!read_vlq(length, event_at)) return false;
    if (end_ - p_ < length) return truncated(event_at);
    p_ += length;
    last_tick_ = tick_;
    after_meta_or_sysex_ = true;
    return true;
  }

  // At most 4 bytes (0x0FFFFFFF); a 5th is an error.
  bool read_vlq(std::uint32_t& out, std::size_t event_at) {
    const std::size_t start = p_;
    std::uint32_t value = 0;
    for (int i = 0; i < 4; ++i) {
      if (p_ >= end_) return truncated(event_at);
      const std::uint8_t b = data_[p_++];
      value = (value << 7) | (b & 0x7Fu);
      if ((b & 0x80) == 0) {
        out = value;
        return true;
      }
    }
    return error(start, "variable-length quantity longer than 4 bytes");
  }

  void note_on(std::uint8_t channel, std::uint8_t key, std::uint8_t velocity) {
    std::uint32_t track = base_track_;
    if (in_.split_by_channel) {
      std::uint32_t& t = channel_track_[channel];
      if (t == kNone) t = base_track_ + split_count_++;
      track = t;
    }
    const auto index = static_cast<std::uint32_t>(st_.notes.size());
    // Sounding, the last of its key so far; the program is filled in by finish_song.
    st_.notes.push_back(Note{tick_, sounding_link(kNoNext), track, channel, key, velocity, 0});
    ParseState::Slot& slot = st_.slot(channel, key);
    if (slot.generation != st_.generation || slot.head == kNone) {
      slot = ParseState::Slot{st_.generation, index, index};
    } else {
      st_.notes[slot.tail].end_tick = sounding_link(index);
      slot.tail = index;
    }
  }

  // Ends the oldest sounding note of the key (first in, first out).
  void note_off(std::uint8_t channel, std::uint8_t key, std::size_t at) {
    ParseState::Slot& slot = st_.slot(channel, key);
    if (slot.generation != st_.generation || slot.head == kNone) {
      orphan_offs_.hit(at);
      return;
    }
    Note& note = st_.notes[slot.head];
    const std::uint32_t next = next_sounding(note.end_tick);
    note.end_tick = tick_;
    slot.head = next == kNoNext ? kNone : next;
  }

  void missing_end_of_track() {
    st_.warnings.add(
        in_.chunk, end_,
        in_.cut_by_eof ? "the file ends before End-of-Track" : "no End-of-Track before the end of the track data");
  }

  bool truncated(std::size_t event_at) {
    st_.warnings.add(in_.chunk, event_at,
                     in_.cut_by_eof ? "event cut off by the end of the file; track ends here"
                                    : "event cut off by the end of the track data; track ends here");
    return false;
  }

  // An error ends the track: events before it are kept.
  bool error(std::size_t at, const char* what) {
    st_.warnings.add(in_.chunk, at, what);
    if (!st_.first_error) st_.first_error = place(in_.chunk, at) + ": " + what;
    return false;
  }

  std::uint64_t finish() {
    const std::uint64_t end_tick = saw_end_of_track_ ? tick_ : last_tick_;
    std::uint64_t still_on = 0;
    for (std::size_t i = first_note_; i < st_.notes.size(); ++i) {
      Note& note = st_.notes[i];
      if (is_sounding(note.end_tick)) {
        note.end_tick = end_tick;
        ++still_on;
      }
    }
    if (running_after_meta_.count > 0) {
      st_.warnings.add(in_.chunk, running_after_meta_.first,
                       times("running status continues after a meta or sysex event", running_after_meta_.count));
    }
    if (orphan_offs_.count > 0) {
      st_.warnings.add(in_.chunk, orphan_offs_.first,
                       times("note-off without a sounding note, ignored", orphan_offs_.count));
    }
    if (malformed_.count > 0) {
      st_.warnings.add(in_.chunk, malformed_.first,
                       times("malformed tempo or time signature event ignored", malformed_.count));
    }
    if (still_on > 0) {
      st_.warnings.add(in_.chunk, p_,
                       std::to_string(still_on) + " notes still sounding at the end of the track; ended there");
    }
    add_tracks(end_tick);
    return end_tick;
  }

  void add_tracks(std::uint64_t end_tick) {
    const std::string& name = has_name_ ? name_ : instrument_;
    const std::uint32_t count = in_.split_by_channel && split_count_ > 0 ? split_count_ : 1;
    for (std::uint32_t k = 0; k < count; ++k) {
      Track t;
      t.index = base_track_ + k;
      t.chunk = in_.chunk;
      t.name = name;
      t.end_tick = end_tick;
      st_.tracks.push_back(std::move(t));
    }
  }

  const std::uint8_t* data_;
  std::span<const std::uint8_t> file_;
  const ChunkInput& in_;
  ParseState& st_;
  std::size_t p_;
  std::size_t end_;
  std::uint64_t tick_;
  std::uint64_t last_tick_;  // tick of the last complete event
  std::size_t first_note_;
  std::uint32_t base_track_;
  std::uint32_t split_count_ = 0;
  std::array<std::uint32_t, 16> channel_track_{};
  std::uint8_t running_ = 0;
  bool after_meta_or_sysex_ = false;
  bool saw_end_of_track_ = false;
  bool has_name_ = false;
  std::string name_;
  std::string instrument_;
  Tally running_after_meta_, orphan_offs_, malformed_;
};

}  // namespace

ChunkResult parse_track(std::span<const std::uint8_t> file, const ChunkInput& in, ParseState& state) {
  return TrackParser(file, in, state).run();
}

}  // namespace hmp::midi::detail
