#pragma once
// How long a frame takes from its start to its swap, which the live view draws ahead by, so that the song
// time a frame shows is the clock's when the frame reaches the screen. The median of the last kFrames
// delays: a single slow frame (the first, which compiles the shaders and takes 50–100 ms; a stall) does not
// move it, where an average would carry it into the frames after; a lasting change is followed within
// half the window.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>

namespace hmp::view {

class PresentDelay {
 public:
  static constexpr std::size_t kFrames = 8;
  using Duration = std::chrono::steady_clock::duration;

  // Until frames are measured: half a 60 Hz period, between an idle GPU's swap and a full frame's wait.
  PresentDelay() { recent_.fill(std::chrono::milliseconds(8)); }

  void add(Duration delay) {
    recent_[next_] = delay;
    next_ = (next_ + 1) % kFrames;
  }
  // The upper median of the last kFrames delays.
  Duration get() const {
    std::array<Duration, kFrames> sorted = recent_;
    std::nth_element(sorted.begin(), sorted.begin() + kFrames / 2, sorted.end());
    return sorted[kFrames / 2];
  }

 private:
  std::array<Duration, kFrames> recent_{};
  std::size_t next_ = 0;
};

}  // namespace hmp::view
