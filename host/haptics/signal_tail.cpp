#include "host/haptics/signal_tail.hpp"

#include <algorithm>
#include <cmath>

namespace hmp::haptics {

SignalTail::SignalTail(std::shared_ptr<const HapticTrack> track, const HapticOptions& opts)
    : track_(std::move(track)), tick_hz_(opts.tick_hz) {
  if (track_) notes_ = track_->device_notes();
  for (const synth::Note& n : notes_) longest_ = std::max<std::uint64_t>(longest_, n.duration_ticks);
  longest_ += static_cast<std::uint64_t>(opts.end_fade_ms * opts.tick_hz / 1000.0) + 1;  // the end fade after it
  settings_ = render_settings(opts);
}

int SignalTail::samples(std::int64_t song_us, float* out, int max) const {
  if (!track_ || max <= 0 || song_us < 0) return 0;
  const double speed = track_->speed > 0 ? track_->speed : 1.0;
  const std::uint64_t now = seconds_to_tick(std::llround(static_cast<double>(song_us) / speed), tick_hz_) + 1;
  const std::uint64_t n = std::min<std::uint64_t>(static_cast<std::uint64_t>(max), now);
  const std::uint64_t first = now - n;
  // Only notes that start before `now` and may still sound at `first`.
  const std::uint64_t earliest = first > longest_ ? first - longest_ : 0;
  auto by_start = [](const synth::Note& a, std::uint64_t t) { return a.start_tick < t; };
  const auto b = std::lower_bound(notes_.begin(), notes_.end(), earliest, by_start);
  const auto e = std::lower_bound(b, notes_.end(), now, by_start);
  const std::vector<float> s = render_signal({b, e}, track_->uploads, settings_, first, now);
  std::copy(s.begin(), s.end(), out);
  return static_cast<int>(s.size());
}

}  // namespace hmp::haptics
