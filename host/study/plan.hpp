#pragma once
// host/study/: the paper's user study (design §15, paper §6–§7). This folder owns the study's logic, free
// of I/O so tests drive it directly: the seeded plan of rounds (plan.*), one round's keys and ranking
// (round.*), the session across rounds with resume (session.*), the results file's rows (results_csv.*)
// and the statistics and Figure 3 of `hmp study analyze` (stats.*, figure.*). The command
// (host/cli/study_command.cpp) reads the keys, from the terminal and from the animation window
// (host/cli/study_view.*), and drives the player; both front-ends drive the same Session.
//
// plan.*: which rounds a participant gets, in which order, with which envelope under which key.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace hmp::study {

enum class Envelope : std::uint8_t { square, triangle, analogue };
inline constexpr std::array<Envelope, 3> kEnvelopes{Envelope::square, Envelope::triangle, Envelope::analogue};
const char* envelope_name(Envelope e);

// The demo's instruments of the study (paper §6), and the two practice ones.
inline constexpr std::array<const char*, 4> kInstruments{"flute", "violin", "contrabass", "harpsichord"};
inline constexpr std::array<const char*, 2> kPracticeInstruments{"violin", "contrabass"};

struct Round {
  int experiment = 1;     // 1: mapping paper, 2: mapping constant
  bool practice = false;  // practice rounds: the instrument alone, results not analysed
  int position = 0;       // 1-based place of the instrument within its experiment (practice: 1, 2)
  std::string instrument;
  std::array<Envelope, 3> by_key{};  // by_key[k]: the envelope under key k
  int key_of(Envelope e) const;
};

const char* mapping_of_experiment(int experiment);  // "paper" or "constant"

// The rounds of a session: the two practice rounds (with the first experiment's mapping), then per
// experiment the four instruments in random order, each with its envelopes in random order. The
// order depends only on (participant, seed, experiments): the same inputs give the same plan.
std::vector<Round> make_plan(const std::string& participant, std::uint64_t seed, const std::vector<int>& experiments);

// A small, fully specified generator (splitmix64), so that a plan is the same on every standard library.
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next();
  std::uint64_t below(std::uint64_t n);  // uniform in [0, n), n > 0
 private:
  std::uint64_t state_;
};

}  // namespace hmp::study
