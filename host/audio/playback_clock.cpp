#include "host/audio/playback_clock.hpp"

#include <algorithm>
#include <cmath>

namespace hmp::audio {

namespace {
double micros(std::chrono::steady_clock::duration d) { return std::chrono::duration<double, std::micro>(d).count(); }
}  // namespace

void PlaybackClock::restart_line(std::int64_t song_us, TimePoint heard_at) {
  origin_time_ = heard_at;
  origin_song_ = song_us;
  offset_ = 0.0;
  reports_.clear();
  off_line_run_ = 0;
}

void PlaybackClock::start(std::int64_t song_us, TimePoint heard_at) {
  running_ = true;
  restart_line(song_us, heard_at);
}

void PlaybackClock::pause(TimePoint now) {
  if (!running_) return;
  paused_us_ = song_us(now);
  running_ = false;
}

std::int64_t PlaybackClock::song_us(TimePoint t) const {
  if (!running_) return paused_us_;
  return origin_song_ + static_cast<std::int64_t>(std::llround(offset_ + slope_ * micros(t - origin_time_)));
}

PlaybackClock::TimePoint PlaybackClock::heard_at(std::int64_t song_us) const {
  const double x = (static_cast<double>(song_us - origin_song_) - offset_) / slope_;
  return origin_time_ +
         std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double, std::micro>(x));
}

void PlaybackClock::observe(std::int64_t song_us, TimePoint heard_at) {
  if (!running_) return;
  const double x = micros(heard_at - origin_time_);
  const double y = static_cast<double>(song_us - origin_song_);
  const double early_us = y - (offset_ + slope_ * x);  // > 0: heard sooner than the line says
  // A callback can run late, never early: a report sooner than the line means the line is late (or
  // the stream restarted sooner); one later than the whole buffer means the card ran dry.
  const bool sooner = early_us > kOffLineUs;
  const bool underrun = -early_us > std::max(buffer_us_, kOffLineUs);
  const bool late = -early_us > kOffLineUs;
  if (sooner || underrun || (late && ++off_line_run_ >= kMinFit)) {
    ++restarts_;
    restart_line(song_us, heard_at);
    return;
  }
  if (late) return;  // a late callback: the card's buffer covered it, the line stands
  off_line_run_ = 0;
  reports_.push_back({x, y});
  if (reports_.size() > kWindow) reports_.pop_front();
  if (reports_.size() >= kMinFit) fit();
}

void PlaybackClock::fit() {
  // Centred sums keep the line well-conditioned however long the song has been playing.
  double mx = 0, my = 0;
  for (const Report& r : reports_) {
    mx += r.x;
    my += r.y;
  }
  const auto n = static_cast<double>(reports_.size());
  mx /= n;
  my /= n;
  double sxx = 0, sxy = 0;
  for (const Report& r : reports_) {
    sxx += (r.x - mx) * (r.x - mx);
    sxy += (r.x - mx) * (r.y - my);
  }
  if (sxx <= 0) return;
  slope_ = std::clamp(sxy / sxx, 1.0 - kMaxSpeedError, 1.0 + kMaxSpeedError);
  offset_ = my - slope_ * mx;
}

}  // namespace hmp::audio
