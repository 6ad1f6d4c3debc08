#pragma once
// A sound card simulated in software, with the truth known: it asks for periods of audio at the pace
// of its own crystal (nominal rate × (1 + ppm)), and the first frame of each period is heard `periods`
// periods after it was asked for (the output latency the audio player assumes of a real card). A
// period that comes back after the card needed it is an underrun: the card plays silence until it
// comes, and everything after is heard that much later. It can keep what it played. The audio–haptic skew is measured
// with it where there is no sound card (tools/bench/e2e_timing.cpp): the audio player sees a card and its callbacks,
// the bench knows exactly when every frame is heard. A real card adds the error of its driver's latency report.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace hmp::audio {

class VirtualCard {
 public:
  using TimePoint = std::chrono::steady_clock::time_point;
  // Fills `frames` frames of the left and right channel (overwritten).
  using Callback = std::function<void(float* left, float* right, int frames)>;

  struct Settings {
    int sample_rate = 48000;
    int period_frames = 256;
    int periods = 4;
    double ppm = 0.0;               // the card's crystal against the host clock: +100 = 100 ppm fast
    std::size_t record_frames = 0;  // keep the first this many frames played (sum of |left| + |right|)
  };

  VirtualCard(const Settings& settings, Callback callback);
  ~VirtualCard();  // stops the thread
  VirtualCard(const VirtualCard&) = delete;
  VirtualCard& operator=(const VirtualCard&) = delete;

  // Host time at which frame `frame` of the stream (0 = the first the card asked for) is heard.
  TimePoint heard_at(double frame) const;
  std::uint64_t underruns() const;
  // Each underrun: where in the stream, how much silence it left, and whether the card's thread woke
  // late for that period or its callback took long (the two causes a real-time thread can have).
  struct Underrun {
    double at_s;          // stream time of the period's first frame, by the card's crystal
    double short_ms;      // how much after it was needed the period came: the silence heard
    double woke_late_ms;  // the thread's wake-up after the period was due
    double callback_ms;   // the callback's run time
  };
  std::vector<Underrun> underrun_list() const;
  double latency_s() const;  // periods × period / rate, by the card's crystal
  // Frames asked for so far, and what was kept of them (call after the card stopped, or accept a
  // snapshot that is still growing).
  std::uint64_t frames_played() const { return frames_.load(); }
  std::vector<float> recording() const;
  void stop();
  // Whether its thread got real-time priority (known once the first period was asked for).
  bool realtime() const { return realtime_.load(); }
  static constexpr int kRealtimePriority = 60;

 private:
  void run();
  double frames_per_second() const { return settings_.sample_rate * (1.0 + settings_.ppm * 1e-6); }

  Settings settings_;
  Callback callback_;
  TimePoint start_;
  std::atomic<std::uint64_t> frames_{0};
  std::atomic<bool> realtime_{false};
  mutable std::mutex mutex_;  // recording_, stop_
  std::condition_variable stop_signal_;
  bool stop_ = false;
  std::vector<float> recording_;
  // Underruns: from stream frame `frame` on, everything is heard `delay` later (cumulative).
  struct Shift {
    std::uint64_t frame;
    std::chrono::steady_clock::duration delay;
    Underrun cause;
  };
  std::vector<Shift> shifts_;
  std::thread thread_;  // last: started once everything above exists
};

}  // namespace hmp::audio
