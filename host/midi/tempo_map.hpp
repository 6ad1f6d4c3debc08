#pragma once
// Tick → time for a Standard MIDI File (design §4), in integer microseconds.
//
// Each segment keeps its start time exactly, as time × the map's common denominator (µs·tpq for
// metrical time), so no rounding error builds up over thousands of tempo changes: a tick's time is
// rounded once, to the nearest µs (halves up). Products go through 128 bits when 64 would overflow;
// times beyond INT64_MAX µs saturate.
#include <cstdint>
#include <vector>

namespace hmp::midi {

inline constexpr std::uint32_t kDefaultTempo = 500000;  // µs per quarter note: 120 bpm

// The header's division field.
struct Division {
  bool smpte = false;
  std::uint16_t ticks_per_quarter = 96;  // metrical (smpte == false)
  std::uint8_t fps = 0;                  // smpte: 24, 25, 29 (= 29.97, 30000/1001) or 30 (any 1–128 accepted)
  std::uint8_t ticks_per_frame = 0;      // smpte
  // Decodes the 16-bit field; fps = −(signed high byte) when the high bit is set.
  static Division from_field(std::uint16_t field);
};

struct TempoChange {
  std::uint64_t tick = 0;
  std::int64_t us = 0;
  std::uint32_t us_per_quarter = kDefaultTempo;
  double bpm() const { return 60e6 / static_cast<double>(us_per_quarter); }
};

class TempoMap {
 public:
  // A tempo event, in file order. Ticks need not be sorted: the map sorts them (stably).
  struct Point {
    std::uint64_t tick = 0;
    std::uint32_t us_per_quarter = kDefaultTempo;
  };

  // 120 bpm at 96 ticks per quarter until built otherwise.
  TempoMap();
  // Metrical time: the default tempo from tick 0, changed by `points`; of several points at one tick the
  // last in file order wins. Points with tempo 0 must be filtered out by the caller. tpq 0 is read as 1.
  static TempoMap metrical(std::uint16_t ticks_per_quarter, std::vector<Point> points);
  // SMPTE time: fixed rate, fps 29 meaning 29.97 (30000/1001); tempo events do not apply.
  // fps or ticks_per_frame 0 are read as 1.
  static TempoMap smpte(std::uint8_t fps, std::uint8_t ticks_per_frame);

  std::int64_t micros(std::uint64_t tick) const;
  // The same, faster for ticks that mostly increase: `hint` remembers the segment of the last call
  // (start it at 0).
  std::int64_t micros(std::uint64_t tick, std::size_t& hint) const;
  double seconds(std::uint64_t tick) const { return static_cast<double>(micros(tick)) * 1e-6; }

  // One TempoChange per segment (empty for SMPTE time); the first is at tick 0.
  std::vector<TempoChange> changes() const;
  bool is_smpte() const { return smpte_; }
  std::size_t segment_count() const { return segments_.size(); }

 private:
  struct Segment {
    std::uint64_t tick = 0;
    std::uint64_t scaled = 0;  // start time × den_ (µs·den); saturates
    std::uint64_t rate = 0;    // µs·den per tick (the tempo in µs per quarter for metrical time)
  };
  std::int64_t micros_in(const Segment& s, std::uint64_t tick) const;

  std::vector<Segment> segments_;  // sorted by tick, segments_[0].tick == 0
  std::uint64_t den_ = 96;         // ticks per quarter (metrical) or 3·ticks per frame·… (SMPTE)
  bool smpte_ = false;
};

}  // namespace hmp::midi
