#include "host/view/note_index.hpp"

#include <algorithm>

namespace hmp::view {

NoteIndex::NoteIndex(const midi::Song& song) : bars_(song.tracks.size()), max_end_(song.tracks.size()) {
  for (const midi::Note& n : song.notes) {
    if (n.track >= bars_.size()) continue;
    bars_[n.track].push_back({song.start_us(n), song.end_us(n), n.key, n.velocity, n.track});
  }
  for (std::size_t t = 0; t < bars_.size(); ++t) {
    std::vector<Bar>& bars = bars_[t];
    std::stable_sort(bars.begin(), bars.end(), [](const Bar& a, const Bar& b) { return a.start_us < b.start_us; });
    std::vector<std::int64_t>& max_end = max_end_[t];
    max_end.resize(bars.size());
    std::int64_t running = INT64_MIN;
    for (std::size_t i = 0; i < bars.size(); ++i) max_end[i] = running = std::max(running, bars[i].end_us);
  }
}

std::size_t NoteIndex::visible(std::uint32_t track, std::int64_t t0_us, std::int64_t t1_us,
                               std::vector<Bar>& out) const {
  out.clear();
  if (track >= bars_.size() || t1_us <= t0_us) return 0;
  const std::vector<Bar>& bars = bars_[track];
  const std::vector<std::int64_t>& max_end = max_end_[track];
  // Every bar before `first` ended at or before t0 (max_end is non-decreasing). A zero-length bar at
  // exactly t0 still shows: hence ≥ for bars that start at t0.
  const auto first = static_cast<std::size_t>(
      std::partition_point(max_end.begin(), max_end.end(), [&](std::int64_t e) { return e < t0_us; }) -
      max_end.begin());
  const auto last = static_cast<std::size_t>(
      std::partition_point(bars.begin(), bars.end(), [&](const Bar& b) { return b.start_us < t1_us; }) - bars.begin());
  for (std::size_t i = first; i < last; ++i) {
    const Bar& b = bars[i];
    if (b.end_us > t0_us || (b.end_us == b.start_us && b.start_us >= t0_us)) out.push_back(b);
  }
  return out.size();
}

}  // namespace hmp::view
