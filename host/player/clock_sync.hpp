#pragma once
// Host clock ↔ device tick (design §10). Each Sync exchange gives one sample: the host time the Sync was
// sent (echoed back by the device), the host time its reply arrived, and the device's position when the
// Sync arrived (tick + sub-tick). A weighted least-squares line through the samples with the shortest
// transit gives the device position at any host time: offset and drift. docs/player.md derives the
// maths and says why a busy host cannot bend the line.
//
// Time bases: host times are µs of std::chrono::steady_clock; device positions are ticks (the tick
// counter plus the fraction of the tick elapsed). Tick k is processed when the position reaches k, so a
// note meant for host time h goes on tick round(position(h)).
//
// Not thread-safe: the caller serialises add() and the queries.
#include <cstdint>
#include <deque>
#include <optional>
#include "shared/synth/tick_rate.hpp"

namespace hmp::player {

struct SyncSample {
  std::int64_t sent_us = 0;      // host time the Sync left (the value it carried)
  std::int64_t received_us = 0;  // host time its SyncReply arrived
  std::uint64_t tick = 0;        // device tick during which the Sync arrived
  std::uint32_t subtick = 0;     // fraction of that tick elapsed on arrival, 2^32 = one tick
};

class ClockSync {
 public:
  // Sub-tick a board reports when its tick interrupt was overdue as the Sync arrived (firmware/board.hpp):
  // the device's tick count lagged its own timer, so tick + 1 is only a lower bound of its clock.
  static constexpr std::uint32_t kOverdueSubtick = 0xFFFFFFFFu;

  struct Options {
    std::uint32_t tick_hz = synth::kNominalTickHz;
    std::size_t window = 64;      // most recent samples kept for the fit
    std::size_t min_samples = 4;  // before this many, ready() is false
    // The fit uses the samples whose transit is within max(this, 25 %) of the lower quartile of the
    // window's transits (at least min_samples of them): their arrival time is known best (a delay on one
    // leg of the trip shifts the estimate by half of it). A quartile, not the minimum: one lucky
    // exchange does not shrink the choice to itself.
    double transit_margin_us = 50.0;
    // Host timing noise that even the quickest exchange has (whole-µs timestamps, timer reads): the
    // floor of every sample's uncertainty, so that near-equal samples weigh near-equally.
    double timing_floor_us = 10.0;
    double min_drift_span_s = 2.0;  // the slope is fitted only once the chosen samples span this much host time
    // |fitted rate / nominal − 1| beyond this: keep the nominal rate. Crystals are within 10⁻⁴, but an
    // emulated board (QEMU on a busy host) loses ticks and runs a few % slow.
    double max_drift = 0.05;
    // Before the slope is fitted, an older sample says less about now: its position, carried forward at
    // the assumed rate, may be off by this much per µs of age (a crystal's tolerance).
    double unfitted_drift = 1e-4;
    // A sample whose whole uncertainty interval is this far off the line, confirmed by the next sample,
    // is a step of the device clock.
    double step_ticks = 8.0;
    // The device answers a Sync when it handles it, at the start of the next tick: the reply waited
    // (1 − sub-tick) ticks on the device, which is not transit time (true of every board of docs/firmware.md).
    bool reply_at_next_tick = true;
  };

  enum class Verdict {
    used,     // the sample is in the fit
    overdue,  // the device's tick was overdue (saturated sub-tick): kept, but only fitted if nothing better
    held,     // off the line beyond its uncertainty and the step threshold: set aside until the next
              // sample says whether the clock stepped (then `step`) or this one was wrong (dropped)
    step,     // this sample confirms the held one: the device clock jumped (an emulator that lost ticks);
              // the fit starts again from the two
    reset,    // the device clock went backwards: the device restarted; the fit starts again from this sample
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
  // How far the line passes outside the uncertainty interval (arrival known to ± half the transit) of
  // the samples in the fit, at worst, in ticks: 0 when it crosses every one of them.
  double max_residual_ticks() const { return max_residual_; }
  std::uint64_t resets() const { return resets_; }
  std::uint64_t steps() const { return steps_; }

 private:
  struct Point {
    // Host times relative to ref_host_us_: the Sync left at `sent_us`; it arrived at the latest at
    // `late_us` (the reply's arrival minus the device's hold), so the transit is late_us − sent_us and
    // the arrival is taken half-way.
    double sent_us;
    double late_us;
    double position;  // device position, relative to ref_tick_
    bool overdue;
    double transit_us() const { return late_us - sent_us; }
    double arrival_us() const { return 0.5 * (sent_us + late_us); }
  };
  double nominal_rate() const { return static_cast<double>(options_.tick_hz) * 1e-6; }  // ticks per µs
  Point to_point(const SyncSample& s) const;
  void restart_from(const SyncSample& s);
  void push(const SyncSample& s);
  std::size_t exact_samples() const;
  double miss_ticks(const Point& p) const;
  bool agree(const Point& a, const Point& b) const;
  void fit();

  Options options_;
  std::deque<Point> samples_;
  std::optional<SyncSample> held_;  // a step candidate waiting for confirmation
  std::int64_t ref_host_us_ = 0;    // first sample's send time (keeps doubles small)
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
