#pragma once
// A participant's whole session (design §15): the plan's rounds one after the other, the rows each
// finished round gives, and resuming: rounds whose rows are already in the results file are skipped.
// No I/O: the front-end passes times in (Unix seconds), reads keys, writes the rows it takes.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "host/study/plan.hpp"
#include "host/study/results_csv.hpp"
#include "host/study/round.hpp"

namespace hmp::study {

struct SessionSpec {
  std::string participant;
  std::uint64_t seed = 0;
  std::vector<int> experiments{1, 2};
  std::string version;
  ParticipantData participant_data;  // as given for this session; a field not given keeps the file's
};

class Session {
 public:
  // `existing`: every row already in the results file. Throws BadInput when this participant's rows
  // there came from another seed (the plan would not be the same), or give another age, sex or
  // handedness than the spec (a field the spec leaves out is taken from them).
  Session(SessionSpec spec, const std::vector<ResultRow>& existing);

  const std::vector<Round>& plan() const { return plan_; }
  std::size_t rounds_done() const;
  const ParticipantData& participant_data() const { return spec_.participant_data; }  // what the rows get
  bool done() const { return next_ >= plan_.size(); }

  // Starts the next round not done yet (call when !done()); the round's state until it finishes.
  RoundState& begin_round(double now_s);
  RoundState* current() { return current_ ? &*current_ : nullptr; }
  // Passes the action to the current round. When it finishes the round: its three rows are ready
  // (take_rows) and, after a practice round, the reply says which key the analogue envelope was.
  Reply act(const Action& a, double now_s);
  std::vector<ResultRow> take_rows();

 private:
  void adopt_participant_data(const ResultRow& recorded);
  void skip_done();
  SessionSpec spec_;
  std::vector<Round> plan_;
  std::vector<bool> done_;
  std::size_t next_ = 0;
  std::optional<RoundState> current_;
  std::vector<ResultRow> ready_;
};

// Keys as typed on the terminal: 0 1 2, a b c (either case), u, Enter / n. Anything else: nothing.
std::optional<Action> action_for_key(char c);

}  // namespace hmp::study
