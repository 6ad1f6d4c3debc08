#include "host/study/plan.hpp"

#include <utility>

namespace hmp::study {

const char* envelope_name(Envelope e) {
  switch (e) {
    case Envelope::square: return "square";
    case Envelope::triangle: return "triangle";
    case Envelope::analogue: return "analogue";
  }
  return "?";
}

int Round::key_of(Envelope e) const {
  for (int k = 0; k < 3; ++k) {
    if (by_key[static_cast<std::size_t>(k)] == e) return k;
  }
  return -1;
}

const char* mapping_of_experiment(int experiment) { return experiment == 2 ? "constant" : "paper"; }

std::uint64_t Random::next() {
  std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

std::uint64_t Random::below(std::uint64_t n) {
  // Rejection keeps it unbiased: draws in the incomplete last block of n are thrown away.
  const std::uint64_t limit = ~std::uint64_t{0} - (~std::uint64_t{0} % n);
  for (;;) {
    const std::uint64_t x = next();
    if (x < limit) return x % n;
  }
}

namespace {

template <class T, std::size_t N>
void shuffle(std::array<T, N>& a, Random& rng) {
  for (std::size_t i = N; i > 1; --i) std::swap(a[i - 1], a[static_cast<std::size_t>(rng.below(i))]);
}

// FNV-1a of the participant's id: mixed into the seed so that participants sharing a seed differ.
std::uint64_t hash_id(const std::string& id) {
  std::uint64_t h = 0xCBF29CE484222325ull;
  for (const unsigned char c : id) h = (h ^ c) * 0x100000001B3ull;
  return h;
}

Round make_round(int experiment, bool practice, int position, const char* instrument, Random& rng) {
  Round r;
  r.experiment = experiment;
  r.practice = practice;
  r.position = position;
  r.instrument = instrument;
  r.by_key = kEnvelopes;
  shuffle(r.by_key, rng);
  return r;
}

}  // namespace

std::vector<Round> make_plan(const std::string& participant, std::uint64_t seed, const std::vector<int>& experiments) {
  Random rng(seed ^ hash_id(participant));
  std::vector<Round> plan;
  if (experiments.empty()) return plan;
  for (std::size_t i = 0; i < kPracticeInstruments.size(); ++i) {
    plan.push_back(make_round(experiments.front(), true, static_cast<int>(i + 1), kPracticeInstruments[i], rng));
  }
  for (const int experiment : experiments) {
    std::array<const char*, 4> order = kInstruments;
    shuffle(order, rng);
    for (std::size_t i = 0; i < order.size(); ++i) {
      plan.push_back(make_round(experiment, false, static_cast<int>(i + 1), order[i], rng));
    }
  }
  return plan;
}

}  // namespace hmp::study
