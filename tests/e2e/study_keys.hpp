#pragma once
// What scripted study participants type (tests/e2e/study_*_test.cpp): per round, the keys a person uses
// to rank the three envelopes in a chosen order, with the detours people take.
#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "host/study/plan.hpp"

namespace hmp::test {

using Preference = std::map<study::Envelope, char>;  // the letter a scripted participant gives each envelope

inline const Preference kAnalogueFirst{
    {study::Envelope::analogue, 'a'}, {study::Envelope::triangle, 'b'}, {study::Envelope::square, 'c'}};
inline const Preference kTriangleFirst{
    {study::Envelope::triangle, 'a'}, {study::Envelope::analogue, 'b'}, {study::Envelope::square, 'c'}};

// The keys of one round, with the detours a person takes: going on too early, a letter already
// taken, an unknown key, an undo.
inline std::string round_keys(const study::Round& r, const Preference& pref) {
  std::string k = "\nx";  // Enter before ranking: refused; x: no meaning
  for (int key = 0; key < 3; ++key) {
    const char letter = pref.at(r.by_key[static_cast<std::size_t>(key)]);
    k += static_cast<char>('0' + key);
    k += letter;
    if (key == 0) k += "u";                   // undo it…
    if (key == 0) k += letter;                // …and rank again
    if (key == 1) k += pref.at(r.by_key[0]);  // a letter key 0 holds: refused
  }
  return k + "\n";
}

// The keys of rounds [from, to) of a participant's plan.
inline std::string session_keys(const std::string& participant, std::uint64_t seed, std::size_t from, std::size_t to,
                                const Preference& exp1, const Preference& exp2,
                                const std::vector<int>& experiments = {1, 2}) {
  const auto plan = study::make_plan(participant, seed, experiments);
  std::string keys;
  for (std::size_t i = from; i < std::min(to, plan.size()); ++i) {
    keys += round_keys(plan[i], plan[i].experiment == 1 ? exp1 : exp2);
  }
  return keys;
}

}  // namespace hmp::test
