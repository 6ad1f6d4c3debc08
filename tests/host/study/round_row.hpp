#pragma once
// A results file's row built in a study test: key k of a round of experiment 1, holding envelope k and
// ranked k + 1, at fixed times.
#include <cstdint>
#include <string>

#include "host/study/results_csv.hpp"

namespace hmp::study::test {

inline ResultRow round_row(const std::string& participant, const std::string& instrument, int k, bool practice,
                           std::uint64_t seed, const std::string& version) {
  ResultRow r;
  r.participant = participant;
  r.experiment = 1;
  r.practice = practice;
  r.position = 1;
  r.instrument = instrument;
  r.mapping = mapping_of_experiment(1);
  r.envelope = kEnvelopes[static_cast<std::size_t>(k)];
  r.key = k;
  r.rank = k + 1;
  r.round_started = 1.8e9;
  r.ranked_at = 1.8e9 + 10;
  r.round_ended = 1.8e9 + 11;
  r.seed = seed;
  r.version = version;
  return r;
}

}  // namespace hmp::study::test
