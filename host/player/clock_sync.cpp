#include "host/player/clock_sync.hpp"
#include "shared/synth/tick_rate.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace hmp::player {

namespace {

// Two readings of the device clock agree when the lines through their uncertainty intervals come
// within this much: far below any step worth the name, far above the host's timing noise.
constexpr double kAgreeTicks = 1.0;

}  // namespace

ClockSync::ClockSync(const Options& options) : options_(options) {
  if (options_.tick_hz == 0) options_.tick_hz = synth::kNominalTickHz;
  options_.min_samples = std::max<std::size_t>(options_.min_samples, 1);
  options_.window = std::max(options_.window, options_.min_samples);
  rate_ = nominal_rate();
}

void ClockSync::clear() {
  // The rate stays: it belongs to the device's oscillator, which a step or a restart does not change.
  samples_.clear();
  held_.reset();
  max_residual_ = 0.0;
}

ClockSync::Point ClockSync::to_point(const SyncSample& s) const {
  const double fraction = static_cast<double>(s.subtick) * 0x1p-32;
  const double round_trip = static_cast<double>(s.received_us - s.sent_us);
  const double hold = options_.reply_at_next_tick ? (1.0 - fraction) / nominal_rate() : 0.0;
  // What is left of the round trip was spent on the link, both ways: the Sync arrived no earlier than it
  // left and no later than that much after.
  const double transit = std::max(0.0, round_trip - hold);
  Point p;
  p.sent_us = static_cast<double>(s.sent_us - ref_host_us_);
  p.late_us = p.sent_us + transit;
  p.position = static_cast<double>(static_cast<std::int64_t>(s.tick - ref_tick_)) + fraction;
  p.overdue = s.subtick == kOverdueSubtick;
  return p;
}

void ClockSync::restart_from(const SyncSample& s) {
  clear();
  ref_host_us_ = s.sent_us;
  ref_tick_ = s.tick;
  push(s);
}

void ClockSync::push(const SyncSample& s) {
  samples_.push_back(to_point(s));
  while (samples_.size() > options_.window) samples_.pop_front();
}

std::size_t ClockSync::exact_samples() const {
  return static_cast<std::size_t>(
      std::count_if(samples_.begin(), samples_.end(), [](const Point& p) { return !p.overdue; }));
}

double ClockSync::miss_ticks(const Point& p) const {
  // The reading was taken somewhere between the send and the latest arrival: the line must pass through
  // [line(sent), line(late)] at that position. How far it misses, 0 when it does not.
  const double at_sent = offset_ + rate_ * p.sent_us;
  const double at_late = offset_ + rate_ * p.late_us;
  return std::max({0.0, at_sent - p.position, p.position - at_late});
}

bool ClockSync::agree(const Point& a, const Point& b) const {
  // The offsets (at the present rate) each reading allows: [position − rate·late, position − rate·sent].
  const double low = std::max(a.position - rate_ * a.late_us, b.position - rate_ * b.late_us);
  const double high = std::min(a.position - rate_ * a.sent_us, b.position - rate_ * b.sent_us);
  return low - high <= kAgreeTicks;
}

ClockSync::Verdict ClockSync::add(const SyncSample& s) {
  if (samples_.empty()) {
    last_tick_ = s.tick;
    restart_from(s);
    fit();
    return s.subtick == kOverdueSubtick ? Verdict::overdue : Verdict::used;
  }
  if (s.tick < last_tick_) {
    // A tick counter only goes back when the device restarted: nothing of the old clock applies.
    ++resets_;
    last_tick_ = s.tick;
    restart_from(s);
    fit();
    return Verdict::reset;
  }
  const Point p = to_point(s);
  // Only an exact reading can say the clock stepped: an overdue one is low by however late the device's
  // tick interrupt ran. And only against a line that exact readings made.
  if (!p.overdue && exact_samples() >= options_.min_samples) {
    const double miss = miss_ticks(p);
    if (miss > options_.step_ticks) {
      if (held_ && agree(to_point(*held_), p)) {
        ++steps_;
        const SyncSample first = *held_;
        last_tick_ = s.tick;
        restart_from(first);
        push(s);
        fit();
        return Verdict::step;
      }
      // One sample off the line may be a glitch: it waits outside the fit for the next one (and its
      // tick does not count as the device's latest until confirmed).
      held_ = s;
      return Verdict::held;
    }
    // On the line, and not where the held sample said the clock went: the held one was wrong. (A wide
    // sample that allows both decides nothing.)
    if (held_ && miss <= kAgreeTicks && !agree(to_point(*held_), p)) held_.reset();
  }
  last_tick_ = s.tick;
  push(s);
  fit();
  return p.overdue ? Verdict::overdue : Verdict::used;
}

void ClockSync::fit() {
  // Exact readings only; overdue ones (lower bounds) only while nothing better exists.
  std::vector<const Point*> chosen;
  chosen.reserve(samples_.size());
  for (const Point& p : samples_) {
    if (!p.overdue) chosen.push_back(&p);
  }
  if (chosen.empty()) {
    for (const Point& p : samples_) chosen.push_back(&p);
  }
  // Of those, the ones that crossed the link fastest: within a margin of the lower quartile of the
  // transits (at least min_samples). A busy host delays some exchanges by milliseconds, on either leg;
  // they stay out, so their one-sided errors cannot tilt the line.
  std::sort(chosen.begin(), chosen.end(),
            [](const Point* a, const Point* b) { return a->transit_us() < b->transit_us(); });
  const double quartile = chosen[(chosen.size() - 1) / 4]->transit_us();
  const std::size_t at_least = std::min(chosen.size(), options_.min_samples);
  const double limit =
      std::max(quartile + std::max(options_.transit_margin_us, 0.25 * quartile), chosen[at_least - 1]->transit_us());
  std::size_t keep = 0;
  while (keep < chosen.size() && chosen[keep]->transit_us() <= limit) ++keep;
  chosen.resize(keep);

  // Each sample's arrival is uncertain by half its transit (plus the timing floor): weights 1/σ².
  // `age_drift` widens older samples when the rate is not known (what an unknown drift does to them by now).
  double newest = chosen.front()->arrival_us(), oldest = newest;
  for (const Point* p : chosen) {
    newest = std::max(newest, p->arrival_us());
    oldest = std::min(oldest, p->arrival_us());
  }
  struct Moments {
    double x_mean = 0.0, y_mean = 0.0, sxx = 0.0, sxy = 0.0;
  };
  auto moments = [&](double age_drift) {
    Moments m;
    double total = 0.0;
    std::vector<double> weights;
    weights.reserve(chosen.size());
    for (const Point* p : chosen) {
      const double sigma = options_.timing_floor_us + 0.5 * p->transit_us() + age_drift * (newest - p->arrival_us());
      weights.push_back(1.0 / (sigma * sigma));
      total += weights.back();
      m.x_mean += weights.back() * p->arrival_us();
      m.y_mean += weights.back() * p->position;
    }
    m.x_mean /= total;
    m.y_mean /= total;
    for (std::size_t i = 0; i < chosen.size(); ++i) {
      const double dx = chosen[i]->arrival_us() - m.x_mean;
      m.sxx += weights[i] * dx * dx;
      m.sxy += weights[i] * dx * (chosen[i]->position - m.y_mean);
    }
    return m;
  };

  const Moments m = moments(0.0);
  bool fitted = false;
  if (chosen.size() >= 3 && newest - oldest >= options_.min_drift_span_s * 1e6 && m.sxx > 0.0) {
    const double rate = m.sxy / m.sxx;
    if (std::isfinite(rate) && std::fabs(rate / nominal_rate() - 1.0) <= options_.max_drift) {
      rate_ = rate;
      fitted = true;
    }
  }
  // Too short a span to see drift: keep the last fitted rate (a crystal's rate does not change), or the
  // nominal one; only the offset is fitted, from the recent samples more than the old ones while the
  // rate is only assumed.
  if (!fitted && !drift_fitted_) rate_ = nominal_rate();
  drift_fitted_ = drift_fitted_ || fitted;
  const Moments o = drift_fitted_ ? m : moments(options_.unfitted_drift);
  offset_ = o.y_mean - rate_ * o.x_mean;

  max_residual_ = 0.0;
  for (const Point* p : chosen) max_residual_ = std::max(max_residual_, miss_ticks(*p));
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
  // An overdue reading's reply left when the device caught up, not on its next tick: its transit means nothing.
  const bool any_exact = exact_samples() > 0;
  double best = 0.0;
  bool any = false;
  for (const Point& p : samples_) {
    if (any_exact && p.overdue) continue;
    if (!any || p.transit_us() < best) best = p.transit_us();
    any = true;
  }
  return best;
}

}  // namespace hmp::player
