#include "host/midi/tempo_map.hpp"

#include <algorithm>
#include <limits>

namespace hmp::midi {
namespace {

constexpr std::uint64_t kU64Max = std::numeric_limits<std::uint64_t>::max();
constexpr std::int64_t kI64Max = std::numeric_limits<std::int64_t>::max();

using u128 = unsigned __int128;

// a + b·c, saturating at 2^64 − 1.
std::uint64_t mul_add_sat(std::uint64_t a, std::uint64_t b, std::uint64_t c) {
  const u128 r = static_cast<u128>(a) + static_cast<u128>(b) * c;
  return r > kU64Max ? kU64Max : static_cast<std::uint64_t>(r);
}

}  // namespace

Division Division::from_field(std::uint16_t field) {
  Division d;
  if ((field & 0x8000u) != 0) {
    d.smpte = true;
    const auto high = static_cast<std::int8_t>(static_cast<std::uint8_t>(field >> 8));
    d.fps = static_cast<std::uint8_t>(-static_cast<int>(high));  // high byte 0x80–0xFF → 128–1 fps
    d.ticks_per_frame = static_cast<std::uint8_t>(field & 0xFFu);
    d.ticks_per_quarter = 0;
  } else {
    d.ticks_per_quarter = field;
  }
  return d;
}

TempoMap::TempoMap() : segments_{Segment{0, 0, kDefaultTempo}} {}

TempoMap TempoMap::metrical(std::uint16_t ticks_per_quarter, std::vector<Point> points) {
  TempoMap map;
  map.den_ = ticks_per_quarter == 0 ? 1 : ticks_per_quarter;
  map.segments_.clear();
  std::stable_sort(points.begin(), points.end(), [](const Point& a, const Point& b) { return a.tick < b.tick; });
  map.segments_.reserve(points.size() + 1);
  map.segments_.push_back(Segment{0, 0, kDefaultTempo});
  for (const Point& p : points) {
    Segment& last = map.segments_.back();
    if (p.tick == last.tick) {  // a later event at the same tick replaces the earlier one
      last.rate = p.us_per_quarter;
      continue;
    }
    const std::uint64_t start = mul_add_sat(last.scaled, p.tick - last.tick, last.rate);
    map.segments_.push_back(Segment{p.tick, start, p.us_per_quarter});
  }
  return map;
}

TempoMap TempoMap::smpte(std::uint8_t fps, std::uint8_t ticks_per_frame) {
  TempoMap map;
  map.smpte_ = true;
  const std::uint64_t tpf = ticks_per_frame == 0 ? 1 : ticks_per_frame;
  if (fps == 29) {
    // 29.97 drop-frame rate is 30000/1001 frames/s: µs per tick = 1001·10^6 / (30000·tpf) = 100100 / (3·tpf).
    map.den_ = 3 * tpf;
    map.segments_ = {Segment{0, 0, 100100}};
  } else {
    map.den_ = static_cast<std::uint64_t>(fps == 0 ? 1 : fps) * tpf;
    map.segments_ = {Segment{0, 0, 1000000}};
  }
  return map;
}

std::int64_t TempoMap::micros_in(const Segment& s, std::uint64_t tick) const {
  const std::uint64_t delta = tick - s.tick;
  std::uint64_t scaled;
  // Fast path in 64 bits; the 128-bit one only when the product could overflow.
  if (delta <= (kU64Max - s.scaled) / (s.rate == 0 ? 1 : s.rate)) {
    scaled = s.scaled + delta * s.rate;
    const std::uint64_t us = scaled / den_ + ((scaled % den_) * 2 >= den_ ? 1 : 0);
    return us > static_cast<std::uint64_t>(kI64Max) ? kI64Max : static_cast<std::int64_t>(us);
  }
  const u128 wide = static_cast<u128>(s.scaled) + static_cast<u128>(delta) * s.rate;
  const u128 us = wide / den_ + ((wide % den_) * 2 >= den_ ? 1 : 0);
  return us > static_cast<u128>(kI64Max) ? kI64Max : static_cast<std::int64_t>(us);
}

std::int64_t TempoMap::micros(std::uint64_t tick) const {
  if (segments_.size() == 1) return micros_in(segments_.front(), tick);
  // Last segment starting at or before tick (segments_[0] starts at 0, so there is one).
  auto it = std::upper_bound(segments_.begin(), segments_.end(), tick,
                             [](std::uint64_t t, const Segment& s) { return t < s.tick; });
  return micros_in(*(it - 1), tick);
}

std::int64_t TempoMap::micros(std::uint64_t tick, std::size_t& hint) const {
  const std::size_t n = segments_.size();
  if (hint >= n) hint = 0;
  // The hinted segment or the next one; anything else by binary search.
  for (std::size_t h = hint; h < n && h <= hint + 1; ++h) {
    if (segments_[h].tick <= tick && (h + 1 == n || tick < segments_[h + 1].tick)) {
      hint = h;
      return micros_in(segments_[h], tick);
    }
  }
  auto it = std::upper_bound(segments_.begin(), segments_.end(), tick,
                             [](std::uint64_t t, const Segment& s) { return t < s.tick; });
  hint = static_cast<std::size_t>(it - segments_.begin()) - 1;
  return micros_in(segments_[hint], tick);
}

std::vector<TempoChange> TempoMap::changes() const {
  std::vector<TempoChange> out;
  if (smpte_) return out;
  out.reserve(segments_.size());
  for (const Segment& s : segments_) {
    out.push_back(TempoChange{s.tick, micros_in(s, s.tick), static_cast<std::uint32_t>(s.rate)});
  }
  return out;
}

}  // namespace hmp::midi
