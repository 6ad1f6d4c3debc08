// After every chunk is read: the global tempo map, each note's program, track statistics. Note times are
// not stored (Song::start_us() computes them), which keeps a note at 24 bytes.
#include <algorithm>
#include <array>
#include <memory>

#include "host/midi/smf_detail.hpp"

namespace hmp::midi::detail {
namespace {

// Program of a channel at a tick, from all program changes of the file.
class ProgramLookup {
 public:
  explicit ProgramLookup(std::vector<ProgramChange>& changes) : changes_(changes) {
    // By channel, then tick; stable so that file order decides among changes at one tick.
    std::stable_sort(changes_.begin(), changes_.end(), [](const ProgramChange& a, const ProgramChange& b) {
      return a.channel != b.channel ? a.channel < b.channel : a.tick < b.tick;
    });
    std::size_t i = 0;
    for (std::uint8_t c = 0; c < 16; ++c) {
      first_[c] = i;
      while (i < changes_.size() && changes_[i].channel == c) ++i;
    }
    first_[16] = i;
  }

  // The latest change at a tick ≤ `tick` (0 when there is none).
  std::uint8_t at(std::uint8_t channel, std::uint64_t tick) const {
    const auto begin = changes_.begin() + static_cast<std::ptrdiff_t>(first_[channel]);
    const auto end = changes_.begin() + static_cast<std::ptrdiff_t>(first_[channel + 1u]);
    if (begin == end) return 0;
    const auto it =
        std::upper_bound(begin, end, tick, [](std::uint64_t t, const ProgramChange& pc) { return t < pc.tick; });
    return it == begin ? 0 : (it - 1)->program;
  }

 private:
  std::vector<ProgramChange>& changes_;
  std::array<std::size_t, 17> first_{};
};

// Per-track statistics of one pass over the notes. Notes come grouped by chunk, and within a chunk a
// (channel, program) pair belongs to exactly one track, so a table per chunk finds a track's ProgramUse.
class TrackStats {
 public:
  void add(Track& t, const Note& n) {
    if (t.chunk != chunk_) {
      chunk_ = t.chunk;
      ++generation_;
    }
    ++t.note_count;
    t.keys.add(n.key);
    t.channels = static_cast<std::uint16_t>(t.channels | (1u << n.channel));
    if ((cleared_channels_ & (1u << n.channel)) == 0) {
      std::fill_n(generation_of_.get() + n.channel * 128u, 128, 0u);
      cleared_channels_ = static_cast<std::uint16_t>(cleared_channels_ | (1u << n.channel));
    }
    const std::size_t pair = n.channel * 128u + n.program;
    if (generation_of_[pair] != generation_) {
      generation_of_[pair] = generation_;
      use_of_[pair] = static_cast<std::uint32_t>(t.programs.size());
      t.programs.push_back(ProgramUse{n.channel, n.program, 0});
    }
    ++t.programs[use_of_[pair]].notes;
  }

 private:
  std::uint32_t chunk_ = 0xFFFFFFFFu;
  std::uint32_t generation_ = 0;  // 0 is no chunk's
  // 16 KiB for every (channel, program) pair, of which a song uses a few channels: a channel's generations
  // are cleared on its first note only, and a use_of_ entry is read only once its generation is set, so
  // the pages of unused channels are never touched (each first touch is a page fault).
  std::uint16_t cleared_channels_ = 0;
  std::unique_ptr<std::uint32_t[]> generation_of_ = std::make_unique_for_overwrite<std::uint32_t[]>(16 * 128);
  std::unique_ptr<std::uint32_t[]> use_of_ = std::make_unique_for_overwrite<std::uint32_t[]>(16 * 128);
};

TempoMap build_tempo_map(const Division& d, std::vector<TempoMap::Point> tempos) {
  if (d.smpte) return TempoMap::smpte(d.fps, d.ticks_per_frame);  // tempo events do not apply
  return TempoMap::metrical(d.ticks_per_quarter, std::move(tempos));
}

}  // namespace

void finish_song(ParseState& st, Song& song) {
  song.tempo_map = build_tempo_map(song.division, std::move(st.tempos));
  const TempoMap& map = song.tempo_map;
  song.tempo_changes = map.changes();

  std::stable_sort(st.time_signatures.begin(), st.time_signatures.end(),
                   [](const TimeSignature& a, const TimeSignature& b) { return a.tick < b.tick; });
  for (TimeSignature& ts : st.time_signatures) ts.us = map.micros(ts.tick);
  song.time_signatures = std::move(st.time_signatures);

  song.tracks = std::move(st.tracks);
  const ProgramLookup programs(st.program_changes);
  TrackStats stats;
  for (Note& n : st.notes) {
    n.program = programs.at(n.channel, n.start_tick);
    stats.add(song.tracks[n.track], n);
  }
  song.notes = std::move(st.notes);
  std::stable_sort(st.controls.begin(), st.controls.end(),
                   [](const Control& a, const Control& b) { return a.tick < b.tick; });
  song.controls = std::move(st.controls);

  song.end_tick = 0;
  for (Track& t : song.tracks) {
    t.end_us = map.micros(t.end_tick);
    song.end_tick = std::max(song.end_tick, t.end_tick);
  }
  song.duration_us = map.micros(song.end_tick);
}

}  // namespace hmp::midi::detail
