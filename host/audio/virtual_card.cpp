#include "host/audio/virtual_card.hpp"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <cmath>

namespace hmp::audio {

VirtualCard::VirtualCard(const Settings& settings, Callback callback)
    : settings_(settings), callback_(std::move(callback)), start_(std::chrono::steady_clock::now()) {
  recording_.reserve(settings_.record_frames);
  thread_ = std::thread([this] { run(); });
}

VirtualCard::~VirtualCard() { stop(); }

void VirtualCard::stop() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  stop_signal_.notify_all();
  if (thread_.joinable()) thread_.join();
}

VirtualCard::TimePoint VirtualCard::heard_at(double frame) const {
  const double seconds =
      (frame + static_cast<double>(settings_.period_frames) * settings_.periods) / frames_per_second();
  std::chrono::steady_clock::duration delay{};
  {
    std::lock_guard lock(mutex_);
    for (const Shift& s : shifts_) {
      if (static_cast<double>(s.frame) <= frame) delay = s.delay;
    }
  }
  return start_ + delay +
         std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(seconds));
}

std::uint64_t VirtualCard::underruns() const {
  std::lock_guard lock(mutex_);
  return shifts_.size();
}

std::vector<VirtualCard::Underrun> VirtualCard::underrun_list() const {
  std::lock_guard lock(mutex_);
  std::vector<Underrun> list;
  for (const Shift& s : shifts_) list.push_back(s.cause);
  return list;
}

double VirtualCard::latency_s() const {
  return static_cast<double>(settings_.period_frames) * settings_.periods / frames_per_second();
}

std::vector<float> VirtualCard::recording() const {
  std::lock_guard lock(mutex_);
  return recording_;
}

void VirtualCard::run() {
  // A sound card's driver thread runs at real-time priority (FluidSynth asks for 60 for the drivers it
  // starts), so that a busy machine does not starve it: the simulated card's thread does the same where
  // the user may have it (root, or an RLIMIT_RTPRIO of 60), and otherwise runs as an ordinary thread.
  sched_param priority{};
  priority.sched_priority = kRealtimePriority;
  realtime_.store(pthread_setschedparam(pthread_self(), SCHED_FIFO, &priority) == 0);
  const auto period = static_cast<std::size_t>(settings_.period_frames);
  std::vector<float> left(period), right(period);
  std::chrono::steady_clock::duration delay{};  // added by underruns so far
  for (std::uint64_t n = 0;; ++n) {
    // Period n is asked for when the card starts playing frame n × period − latency: its first frame
    // is then heard exactly one latency later, as the audio player assumes of a real card.
    const TimePoint due = delay + start_ +
                          std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                              std::chrono::duration<double>(static_cast<double>(n * period) / frames_per_second()));
    {
      std::unique_lock lock(mutex_);
      if (stop_signal_.wait_until(lock, due, [this] { return stop_; })) return;
    }
    const TimePoint woke = std::chrono::steady_clock::now();
    std::fill(left.begin(), left.end(), 0.0f);
    std::fill(right.begin(), right.end(), 0.0f);
    callback_(left.data(), right.data(), settings_.period_frames);
    const TimePoint needed = heard_at(static_cast<double>(n * period));
    const TimePoint ready = std::chrono::steady_clock::now();
    frames_.fetch_add(period);
    std::lock_guard lock(mutex_);
    if (ready > needed) {  // the card ran dry: silence until now, the rest comes later
      delay += ready - needed;
      const auto ms = [](std::chrono::steady_clock::duration d) {
        return std::chrono::duration<double, std::milli>(d).count();
      };
      shifts_.push_back({n * period,
                         delay,
                         {static_cast<double>(n * period) / frames_per_second(), ms(ready - needed), ms(woke - due),
                          ms(ready - woke)}});
    }
    for (std::size_t i = 0; i < period && recording_.size() < settings_.record_frames; ++i) {
      recording_.push_back(std::fabs(left[i]) + std::fabs(right[i]));
    }
  }
}

}  // namespace hmp::audio
