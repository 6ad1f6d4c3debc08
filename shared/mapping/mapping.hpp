#pragma once
// Pitch → haptic frequency and amplitude (design §5; paper Eq. 5–7; 2013 paper Eq. 2–5).
// Computed on the host per haptic track, in double. Freestanding: keys live in a 128-bit set.
#include <cstdint>

namespace hmp::mapping {

enum class Mode : std::uint8_t { paper, rank, constant, legacy2013 };
const char* name(Mode m);
bool find_mode(const char* name, Mode& out);  // case-insensitive

struct Ranges {
  double f_min_hz = 50, f_max_hz = 250;  // design §5 defaults
  double a_min_db = 7.5, a_max_db = 30;  // a_max is full scale (1.0)
};
// Usable ranges: all finite, 0 < f_min ≤ f_max, a_min ≤ a_max. A Mapper given others uses the defaults
// (the host rejects them first, with a message).
bool valid(const Ranges& r);
// The 2013 paper's ranges: 60–200 Hz, amplitude 3.8–5.0 (device units; 5.0 = full scale).
inline constexpr double kLegacyFminHz = 60, kLegacyFmaxHz = 200, kLegacyAmin = 3.8, kLegacyAmax = 5.0;
// force_min of the 2013 paper's Eq. 6 (end level of the damped sine), in full-scale units.
inline constexpr double kLegacyForceMin = 0.05;

// The set of MIDI keys (0–127) a track uses.
class KeySet {
 public:
  void add(std::uint8_t key);  // keys above 127 are ignored
  bool contains(std::uint8_t key) const;
  int count() const;                        // k_ε
  int min() const;                          // k_min (−1 when empty)
  int max() const;                          // k_max (−1 when empty)
  int rank(std::uint8_t key) const;         // 0-based rank among the distinct keys (−1 if absent)
  int count_below(std::uint8_t key) const;  // keys of the set lower than key (= rank when present)
 private:
  std::uint64_t bits_[2] = {0, 0};
};

struct Haptic {
  double freq_hz = 0;
  double amplitude = 0;  // linear, full scale = 1.0
};

// a_h = 10^((a_dB − a_max)/20).
double db_to_linear(double a_db, double a_max_db);

class Mapper {
 public:
  Mapper(Mode mode, const Ranges& ranges, const KeySet& keys);
  // Keys of the set map as design §5 says. An empty set maps every key to the middle of the ranges
  // (paper/rank: n/k_ε = 1/2; legacy2013: n' = 1/2). Keys outside [k_min, k_max] are clamped to it;
  // in rank mode a key between two keys of the set gets the rank half-way between theirs.
  Haptic map(std::uint8_t key) const;
  // How many frequency just-noticeable differences (18 %) the track's mapped frequencies span.
  double jnd_steps() const;
  // The same for the mapped frequencies of other keys (a track's own, when the set is the song's).
  double jnd_steps(const KeySet& keys) const;

 private:
  Mode mode_;
  Ranges ranges_;
  KeySet keys_;
};

}  // namespace hmp::mapping
