#pragma once
// One round of the study (design §15): the participant switches between the three envelopes with keys
// 0/1/2 at any time, gives each the rank A, B or C (the envelope felt at the moment gets the letter; each
// letter once), may undo the last rank, and can go on only when all three are ranked. Times come from
// the caller (seconds on any steady clock), so the round is pure logic.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "host/study/plan.hpp"

namespace hmp::study {

// What a participant can do; the terminal maps keys to these (0/1/2, a/b/c, u, Enter).
struct Action {
  enum class Kind { select, rank, undo, next } kind = Kind::next;
  int value = 0;  // select: key 0–2; rank: 0 = A (best), 1 = B, 2 = C
};

// The answer to an action: a line for the participant, and what changed.
struct Reply {
  std::string message;
  bool accepted = false;
  bool envelope_changed = false;  // select: the player must switch to the new envelope
  bool finished = false;          // next with all three ranked: the round is over
};

struct EnvelopeResult {
  Envelope envelope{};
  int key = 0;
  int rank = 0;             // 1 = A (best) … 3 = C
  double seconds_felt = 0;  // time this envelope was the one playing
  int times_selected = 0;   // switches to it (the start of the round counts for key 0)
  double ranked_at_s = 0;   // when it got its (final) rank
};

class RoundState {
 public:
  RoundState(Round round, double now_s);  // key 0 plays first
  Reply act(const Action& a, double now_s);
  const Round& round() const { return round_; }
  int selected_key() const { return selected_; }
  Envelope selected_envelope() const { return round_.by_key[static_cast<std::size_t>(selected_)]; }
  bool finished() const { return finished_; }
  std::optional<int> rank_of_key(int key) const { return ranks_[static_cast<std::size_t>(key)]; }
  // The three results in key order; valid once finished() (times up to the finishing action).
  std::vector<EnvelopeResult> results() const;
  double started_s() const { return started_s_; }
  double ended_s() const { return ended_s_; }
  std::string prompt() const;  // what the participant sees: keys, ranks so far, what is missing

 private:
  void account(double now_s);
  Round round_;
  int selected_ = 0;
  bool finished_ = false;
  double started_s_ = 0, ended_s_ = 0, since_s_ = 0;
  std::array<std::optional<int>, 3> ranks_{};  // by key: 0 = A …
  std::array<double, 3> felt_{}, ranked_at_{};
  std::array<int, 3> selected_count_{};
  std::vector<int> rank_history_;  // keys in the order they were ranked (undo pops)
};

char rank_letter(int rank_index);  // 0 → 'A'

}  // namespace hmp::study
