#pragma once
// Host clock ↔ device tick (SPEC §10). Each Sync exchange gives one sample: the host time the Sync was
// sent (echoed back by the device), the host time its reply arrived, and the device's position when the
// Sync arrived (tick + sub-tick). A least-squares line through the samples with the shortest transit
// gives the device position at any host time: offset and drift. docs/player.md derives the maths.
//
// Time bases: host times are µs of std::chrono::steady_clock; device positions are ticks (the tick
// counter plus the fraction of the tick elapsed). Tick k is processed when the position reaches k, so a
// note meant for host time h goes on tick round(position(h)).
//
// Not thread-safe: the caller serialises add() and the queries.
#include <cstdint>
#include <deque>
#include <optional>

namespace hmp::player {

struct SyncSample {
  std::int64_t sent_us = 0;      // host time the Sync left (the value it carried)
  std::int64_t received_us = 0;  // host time its SyncReply arrived
  std::uint64_t tick = 0;        // device tick during which the Sync arrived
  std::uint32_t subtick = 0;     // fraction of that tick elapsed on arrival, 2^32 = one tick
};

class ClockSync {
 public:
  struct Options {
    std::uint32_t tick_hz = 1000;
    std::size_t window = 64;          // most recent samples kept for the fit
    std::size_t min_samples = 4;      // before this many, ready() is false
    // The fit uses the samples whose transit is within max(this, 25 %) of the quickest one: their
    // arrival time is known best (a delay on one leg of the trip shifts the estimate by half of it).
    double transit_margin_us = 50.0;
    double min_drift_span_s = 2.0;    // the slope is fitted only over at least this much host time
    // |fitted rate / nominal − 1| beyond this: keep the nominal rate. Crystals are within 10⁻⁴, but an
    // emulated board (QEMU on a busy host) loses ticks and runs a few % slow.
    double max_drift = 0.05;
    double step_ticks = 8.0;          // a sample this far off the line (beyond its own uncertainty): the clock stepped
    // The device answers a Sync when it handles it, at the start of the next tick: the reply waited
    // (1 − sub-tick) ticks on the device, which is not transit time (true of every board of docs/firmware.md).
    bool reply_at_next_tick = true;
  };

  enum class Verdict {
    used,   // the sample is in the fit
    step,   // the device clock jumped (an emulator that lost ticks): the fit starts again from this sample
    reset,  // the device clock went backwards: the device restarted; the fit starts again from this sample
  };

  explicit ClockSync(const Options& options);

  Verdict add(const SyncSample& s);
  void clear();  // forgets the samples, keeps the fitted rate

  bool ready() const { return samples_.size() >= options_.min_samples; }
  std::size_t samples() const { return samples_.size(); }
  // Device position (ticks) at host time `host_us`; the nominal rate through the one sample when only
  // one exists; nullopt with none.
  std::optional<double> position(std::int64_t host_us) const;
  // The tick a note heard at `host_us` starts on: round(position) (halves up).
  std::optional<std::uint64_t> tick_at(std::int64_t host_us) const;
  // Host time at device position `ticks` (the inverse of position()).
  std::optional<double> host_us_at(double ticks) const;

  // Fitted rate relative to the nominal tick rate, minus 1 (e.g. 50e-6 = the device runs 50 ppm fast).
  double drift() const { return rate_ / nominal_rate() - 1.0; }
  bool drift_fitted() const { return drift_fitted_; }
  // Shortest transit among the samples (round trip minus the device's hold), µs.
  double best_transit_us() const;
  // Largest |residual| of the samples in the fit, in ticks (how well the line explains them).
  double max_residual_ticks() const { return max_residual_; }
  std::uint64_t resets() const { return resets_; }
  std::uint64_t steps() const { return steps_; }

 private:
  struct Point {
    double host_us;     // estimated host time of the Sync's arrival, relative to ref_host_us_
    double position;    // device position, relative to ref_tick_
    double transit_us;  // round trip minus hold: the uncertainty of host_us is half of it
  };
  double nominal_rate() const { return static_cast<double>(options_.tick_hz) * 1e-6; }  // ticks per µs
  Point to_point(const SyncSample& s) const;
  void fit();

  Options options_;
  std::deque<Point> samples_;
  std::int64_t ref_host_us_ = 0;  // first sample's arrival (keeps doubles small)
  std::uint64_t ref_tick_ = 0;
  std::uint64_t last_tick_ = 0;
  // position(h) = offset_ + rate_ × (h − ref_host_us_) + ref_tick_
  double offset_ = 0.0;
  double rate_ = 0.0;
  bool drift_fitted_ = false;
  double max_residual_ = 0.0;
  std::uint64_t resets_ = 0;
  std::uint64_t steps_ = 0;
};

}  // namespace hmp::player
