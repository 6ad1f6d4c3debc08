#include "host/player/clock_sync.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

namespace hmp::player {

ClockSync::ClockSync(const Options& options) : options_(options) {
  if (options_.tick_hz == 0) options_.tick_hz = 1000;
  options_.min_samples = std::max<std::size_t>(options_.min_samples, 1);
  options_.window = std::max(options_.window, options_.min_samples);
  rate_ = nominal_rate();
}

void ClockSync::clear() {
  // The rate stays: it belongs to the device's oscillator, which a step or a restart does not change.
  samples_.clear();
  max_residual_ = 0.0;
}

ClockSync::Point ClockSync::to_point(const SyncSample& s) const {
  const double fraction = static_cast<double>(s.subtick) * 0x1p-32;
  const double round_trip = static_cast<double>(s.received_us - s.sent_us);
  const double hold = options_.reply_at_next_tick ? (1.0 - fraction) / nominal_rate() : 0.0;
  // Of the round trip, the part spent on the wire (both ways) is split evenly: the Sync arrived half
  // the transit after it left.
  const double transit = std::max(0.0, round_trip - hold);
  Point p;
  p.host_us = static_cast<double>(s.sent_us - ref_host_us_) + transit / 2.0;
  p.position = static_cast<double>(static_cast<std::int64_t>(s.tick - ref_tick_)) + fraction;
  p.transit_us = transit;
  return p;
}

ClockSync::Verdict ClockSync::add(const SyncSample& s) {
  Verdict verdict = Verdict::used;
  if (!samples_.empty()) {
    if (s.tick < last_tick_) {
      verdict = Verdict::reset;  // a tick counter only goes back when the device restarted
      ++resets_;
    } else if (ready()) {
      const Point p = to_point(s);
      const double predicted = offset_ + rate_ * p.host_us;
      // The arrival time is known to ± half the transit: only a jump beyond that (and the threshold)
      // says the clock is not the one fitted.
      const double slack = options_.step_ticks + rate_ * p.transit_us / 2.0;
      if (std::fabs(p.position - predicted) > slack) {
        verdict = Verdict::step;
        ++steps_;
      }
    }
    if (verdict != Verdict::used) clear();
  }
  if (samples_.empty()) {
    ref_host_us_ = s.sent_us;
    ref_tick_ = s.tick;
  }
  last_tick_ = s.tick;
  samples_.push_back(to_point(s));
  while (samples_.size() > options_.window) samples_.pop_front();
  fit();
  return verdict;
}

void ClockSync::fit() {
  // The samples that crossed the link fastest carry the least timing noise: those within a small margin
  // of the quickest transit (at least min_samples of them). Ties all count, so that the chosen samples
  // spread over the window rather than depend on the sorting.
  std::vector<const Point*> best;
  best.reserve(samples_.size());
  for (const Point& p : samples_) best.push_back(&p);
  std::sort(best.begin(), best.end(), [](const Point* a, const Point* b) { return a->transit_us < b->transit_us; });
  const double quickest = best.front()->transit_us;
  const std::size_t at_least = std::min(best.size(), options_.min_samples);
  const double limit = std::max(quickest + std::max(options_.transit_margin_us, 0.25 * quickest), best[at_least - 1]->transit_us);
  std::size_t keep = 0;
  while (keep < best.size() && best[keep]->transit_us <= limit) ++keep;
  best.resize(keep);

  double x_min = best.front()->host_us, x_max = x_min;
  double x_mean = 0.0, y_mean = 0.0;
  for (const Point* p : best) {
    x_min = std::min(x_min, p->host_us);
    x_max = std::max(x_max, p->host_us);
    x_mean += p->host_us;
    y_mean += p->position;
  }
  x_mean /= static_cast<double>(keep);
  y_mean /= static_cast<double>(keep);

  bool fitted = false;
  if (keep >= 3 && x_max - x_min >= options_.min_drift_span_s * 1e6) {
    double sxx = 0.0, sxy = 0.0;
    for (const Point* p : best) {
      sxx += (p->host_us - x_mean) * (p->host_us - x_mean);
      sxy += (p->host_us - x_mean) * (p->position - y_mean);
    }
    const double rate = sxy / sxx;
    if (std::isfinite(rate) && std::fabs(rate / nominal_rate() - 1.0) <= options_.max_drift) {
      rate_ = rate;
      fitted = true;
    }
  }
  // Too short a span to see drift: keep the last fitted rate (a crystal's rate does not change), or the
  // nominal one; only the offset is fitted.
  if (!fitted && !drift_fitted_) rate_ = nominal_rate();
  drift_fitted_ = drift_fitted_ || fitted;
  offset_ = y_mean - rate_ * x_mean;

  max_residual_ = 0.0;
  for (const Point* p : best) max_residual_ = std::max(max_residual_, std::fabs(p->position - offset_ - rate_ * p->host_us));
}

std::optional<double> ClockSync::position(std::int64_t host_us) const {
  if (samples_.empty()) return std::nullopt;
  const double x = static_cast<double>(host_us - ref_host_us_);
  return static_cast<double>(ref_tick_) + offset_ + rate_ * x;
}

std::optional<std::uint64_t> ClockSync::tick_at(std::int64_t host_us) const {
  if (samples_.empty()) return std::nullopt;
  // Rounded relative to the reference tick, so that large tick counts keep every bit.
  const double relative = std::floor(offset_ + rate_ * static_cast<double>(host_us - ref_host_us_) + 0.5);
  const auto step = static_cast<std::int64_t>(relative);
  if (step < 0 && static_cast<std::uint64_t>(-step) > ref_tick_) return 0;
  return ref_tick_ + static_cast<std::uint64_t>(step);
}

std::optional<double> ClockSync::host_us_at(double ticks) const {
  if (samples_.empty()) return std::nullopt;
  return static_cast<double>(ref_host_us_) + (ticks - static_cast<double>(ref_tick_) - offset_) / rate_;
}

double ClockSync::best_transit_us() const {
  double best = 0.0;
  bool any = false;
  for (const Point& p : samples_) {
    if (!any || p.transit_us < best) best = p.transit_us;
    any = true;
  }
  return best;
}

}  // namespace hmp::player
