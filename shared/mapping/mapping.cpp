#include "shared/mapping/mapping.hpp"

#include <bit>
#include <cmath>

#include "shared/common/text.hpp"

namespace hmp::mapping {

namespace {

constexpr const char* kModeNames[] = {"paper", "rank", "constant", "legacy2013"};
constexpr int kModeCount = 4;
constexpr int kKeyCount = 128;

// The skin's frequency just-noticeable difference (paper §5.4: 18 %).
constexpr double kFrequencyJnd = 1.18;
// The paper's experiment 2: every note at 250 Hz and full amplitude.
constexpr double kConstantHz = 250.0;

// Keys outside the set's range map like its nearest end.
int clamp_key(int key, int lo, int hi) { return key < lo ? lo : (key > hi ? hi : key); }

// Rounding of the formulas below can overshoot a range end by an ulp; callers rely on the ranges.
double clamp(double v, double lo, double hi) { return v < lo ? lo : (v > hi ? hi : v); }

Haptic in_ranges(const Ranges& r, double f_hz, double a_db) {
  return {clamp(f_hz, r.f_min_hz, r.f_max_hz), db_to_linear(clamp(a_db, r.a_min_db, r.a_max_db), r.a_max_db)};
}

// Eq. 5–7 as printed: n = k_ε (k − k_min)/Δk, then f and a_dB move by Δ/k_ε per unit of n.
Haptic map_paper(const Ranges& r, const KeySet& keys, int key) {
  const int k_eps = keys.count();
  const int k_min = keys.min();
  const int delta_k = keys.max() - k_min;
  double n;
  double k_eps_d = k_eps;
  if (k_eps == 0) {
    k_eps_d = 1;  // empty track: the middle, as for one key
    n = 0.5;
  } else if (delta_k == 0) {
    n = k_eps_d / 2;
  } else {
    n = k_eps_d * (clamp_key(key, k_min, keys.max()) - k_min) / delta_k;
  }
  return in_ranges(r, r.f_min_hz + (r.f_max_hz - r.f_min_hz) / k_eps_d * n,
                   r.a_min_db + (r.a_max_db - r.a_min_db) / k_eps_d * n);
}

// Position i/(k_ε − 1) of the key among the distinct keys, in [0, 1]; 1/2 with fewer than two keys.
double rank_position(const KeySet& keys, int key) {
  const int k_eps = keys.count();
  if (k_eps < 2) return 0.5;
  const int k = clamp_key(key, keys.min(), keys.max());
  const auto key8 = static_cast<std::uint8_t>(k);
  // An absent key sits between its neighbours: half a rank below the next key of the set.
  const double i = keys.contains(key8) ? keys.count_below(key8) : keys.count_below(key8) - 0.5;
  return i / (k_eps - 1);
}

Haptic map_rank(const Ranges& r, const KeySet& keys, int key) {
  const double u = rank_position(keys, key);
  return in_ranges(r, r.f_min_hz * std::pow(r.f_max_hz / r.f_min_hz, u), r.a_min_db + (r.a_max_db - r.a_min_db) * u);
}

// 2013 paper Eq. 3–5 with its note_step divided by the number of distinct keys:
// n' = (k − k_min)/(Δk + 1) ∈ [0, 1), so f stays below 200 Hz (the printed note_step would exceed it).
Haptic map_legacy(const KeySet& keys, int key) {
  double step = 0.5;  // empty track: the middle
  if (keys.count() > 0) {
    const int k_min = keys.min();
    step = static_cast<double>(clamp_key(key, k_min, keys.max()) - k_min) / (keys.max() - k_min + 1);
  }
  const double f = kLegacyFminHz + step * (kLegacyFmaxHz - kLegacyFminHz);
  const double amp_device = kLegacyAmin + step * (kLegacyAmax - kLegacyAmin);
  return {f, amp_device / kLegacyAmax};
}

}  // namespace

const char* name(Mode m) {
  const auto i = static_cast<int>(m);
  return i < kModeCount ? kModeNames[i] : "unknown";
}

bool find_mode(const char* wanted, Mode& out) {
  for (int i = 0; i < kModeCount; ++i) {
    if (text::iequals(wanted, kModeNames[i])) {
      out = static_cast<Mode>(i);
      return true;
    }
  }
  return false;
}

bool valid(const Ranges& r) {
  return std::isfinite(r.f_min_hz) && std::isfinite(r.f_max_hz) && std::isfinite(r.a_min_db) &&
         std::isfinite(r.a_max_db) && r.f_min_hz > 0 && r.f_min_hz <= r.f_max_hz && r.a_min_db <= r.a_max_db;
}

void KeySet::add(std::uint8_t key) {
  if (key < kKeyCount) bits_[key / 64] |= std::uint64_t{1} << (key % 64);
}

bool KeySet::contains(std::uint8_t key) const { return key < kKeyCount && ((bits_[key / 64] >> (key % 64)) & 1u) != 0; }

int KeySet::count() const { return std::popcount(bits_[0]) + std::popcount(bits_[1]); }

int KeySet::min() const {
  if (bits_[0] != 0) return std::countr_zero(bits_[0]);
  if (bits_[1] != 0) return 64 + std::countr_zero(bits_[1]);
  return -1;
}

int KeySet::max() const {
  if (bits_[1] != 0) return 127 - std::countl_zero(bits_[1]);
  if (bits_[0] != 0) return 63 - std::countl_zero(bits_[0]);
  return -1;
}

int KeySet::count_below(std::uint8_t key) const {
  if (key >= kKeyCount) return count();
  // All of the low word when key ≥ 64, plus the bits under key in its own word.
  const std::uint64_t below_in_word = (std::uint64_t{1} << (key % 64)) - 1;
  const int low_word = key >= 64 ? std::popcount(bits_[0]) : 0;
  return low_word + std::popcount(bits_[key / 64] & below_in_word);
}

int KeySet::rank(std::uint8_t key) const { return contains(key) ? count_below(key) : -1; }

double db_to_linear(double a_db, double a_max_db) { return std::pow(10.0, (a_db - a_max_db) / 20.0); }

Mapper::Mapper(Mode mode, const Ranges& ranges, const KeySet& keys)
    : mode_(mode), ranges_(valid(ranges) ? ranges : Ranges{}), keys_(keys) {}

Haptic Mapper::map(std::uint8_t key) const {
  switch (mode_) {
    case Mode::paper: return map_paper(ranges_, keys_, key);
    case Mode::rank: return map_rank(ranges_, keys_, key);
    case Mode::constant: return {kConstantHz, 1.0};
    case Mode::legacy2013: return map_legacy(keys_, key);
  }
  return map_paper(ranges_, keys_, key);  // an out-of-range Mode value: the default mode
}

double Mapper::jnd_steps() const { return jnd_steps(keys_); }

double Mapper::jnd_steps(const KeySet& keys) const {
  double lo = 0, hi = 0;
  bool any = false;
  for (int k = 0; k < kKeyCount; ++k) {
    const auto key = static_cast<std::uint8_t>(k);
    if (!keys.contains(key)) continue;
    const double f = map(key).freq_hz;
    lo = any ? std::fmin(lo, f) : f;
    hi = any ? std::fmax(hi, f) : f;
    any = true;
  }
  if (!any || !(lo > 0)) return 0;
  return std::log(hi / lo) / std::log(kFrequencyJnd);
}

}  // namespace hmp::mapping
