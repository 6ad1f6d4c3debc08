#include "host/player/scheduler.hpp"

#include <algorithm>
#include <cmath>

namespace hmp::player {

std::int64_t seconds_to_us(double s) { return std::llround(s * 1e6); }

void Scheduler::load(const haptics::HapticTrack& track, std::int64_t song_us) {
  notes_.clear();
  track_ = track.track;
  last_end_us_ = from_us_;
  for (const haptics::HapticNote& n : track.notes) {
    const std::int64_t start = seconds_to_us(n.start_s);
    if (start < from_us_ || start >= to_us_) continue;
    notes_.push_back({{start, n.channel, n.program, n.key}, seconds_to_us(n.end_s), n.note, n.start_s});
    Entry& e = notes_.back();
    if (e.end_us > to_us_) {
      // The passage ends at --to, as render and sim end it: a note still sounding there stops there (a
      // note that never ends, a missing note-off, would otherwise hold the device for hours).
      const double kept = static_cast<double>(to_us_ - start) / static_cast<double>(e.end_us - start);
      e.note.duration_ticks = static_cast<std::uint32_t>(
          std::max<long long>(1, std::llround(static_cast<double>(e.note.duration_ticks) * kept)));
      e.end_us = to_us_;
    }
    last_end_us_ = std::max(last_end_us_, notes_.back().end_us);
  }
  // build_haptic_track sorts by tick; the same order by µs (ticks are rounded µs), ties kept.
  std::stable_sort(notes_.begin(), notes_.end(),
                   [](const Entry& a, const Entry& b) { return a.sound.start_us < b.sound.start_us; });
  seek(song_us);
}

void Scheduler::seek(std::int64_t song_us) {
  const std::int64_t at = std::max(song_us, from_us_);
  cursor_ =
      static_cast<std::size_t>(std::lower_bound(notes_.begin(), notes_.end(), at,
                                                [](const Entry& e, std::int64_t t) { return e.sound.start_us < t; }) -
                               notes_.begin());
}

std::optional<PendingReport> Scheduler::next(std::uint64_t horizon, std::uint64_t stale_tick,
                                             const std::function<std::uint64_t(const NoteSound&)>& tick_of) {
  std::vector<DeviceNote> batch;
  PendingReport report;
  while (cursor_ < notes_.size() && batch.size() < protocol::kNotesPerBatch) {
    const Entry& e = notes_[cursor_];
    std::uint64_t tick = tick_of(e.sound);
    if (tick > horizon) break;
    if (tick + e.note.duration_ticks < stale_tick) {
      ++skipped_;
      ++cursor_;
      continue;
    }
    // A refit of the clock between two notes could put a later note a tick before an earlier one; a
    // batch wants its notes at or after its base, so a note never goes before its predecessor.
    if (!batch.empty() && tick < batch.back().start_tick) tick = batch.back().start_tick;
    DeviceNote d = e.note;
    d.start_tick = tick;
    // Only notes that fit the report begun by the first one (make_report's rules) are taken here.
    if (!batch.empty()) {
      std::vector<DeviceNote> trial = batch;
      trial.push_back(d);
      protocol::Message m;
      if (make_report(trial, m) != trial.size()) break;
    }
    batch.push_back(d);
    report.notes.push_back({track_, e.sound.key, e.start_s, tick, d.duration_ticks});
    ++cursor_;
    if (d.duration_ticks > protocol::kMaxCompactDuration) break;  // a LongNote travels alone
  }
  if (batch.empty()) return std::nullopt;
  make_report(batch, report.message);
  return report;
}

}  // namespace hmp::player
