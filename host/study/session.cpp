#include "host/study/session.hpp"

#include <utility>

#include <fmt/format.h>

#include "host/common/error.hpp"
#include "host/common/printable.hpp"

namespace hmp::study {

Session::Session(SessionSpec spec, const std::vector<ResultRow>& existing)
    : spec_(std::move(spec)),
      plan_(make_plan(spec_.participant, spec_.seed, spec_.experiments)),
      done_(plan_.size(), false) {
  bool adopted = false;
  for (const ResultRow& r : existing) {
    if (r.participant != spec_.participant) continue;
    if (r.seed != spec_.seed) {
      throw BadInput(
          fmt::format("participant {} already has results with seed {} (line {}): resume with --seed {}, or "
                      "use another participant id",
                      spec_.participant, r.seed, r.line, r.seed));
    }
    if (!adopted) adopt_participant_data(r);  // the file's rows agree with each other (parse_results)
    adopted = true;
    for (std::size_t i = 0; i < plan_.size(); ++i) {
      const Round& p = plan_[i];
      if (p.experiment == r.experiment && p.practice == r.practice && p.instrument == r.instrument) done_[i] = true;
    }
  }
  skip_done();
}

// The recorded data goes on in the new rows: a field given again must be the recorded one, a field left
// out is taken from the row.
void Session::adopt_participant_data(const ResultRow& recorded) {
  ParticipantData& given = spec_.participant_data;
  const ParticipantData& before = recorded.participant_data;
  const ParticipantData merged{given.age ? given.age : before.age, given.sex ? given.sex : before.sex,
                               given.handedness ? given.handedness : before.handedness};
  const std::string difference = participant_difference(
      merged, before, fmt::format("{}:{}", printable(recorded.file), recorded.line), participant_columns());
  if (!difference.empty()) {
    throw BadInput(fmt::format("participant {}: {} (a participant's rows must agree; leave the option out to keep it)",
                               spec_.participant, difference));
  }
  given = merged;
}

void Session::skip_done() {
  while (next_ < plan_.size() && done_[next_]) ++next_;
}

std::size_t Session::rounds_done() const {
  std::size_t n = 0;
  for (const bool d : done_) n += d ? 1 : 0;
  return n;
}

RoundState& Session::begin_round(double now_s) {
  current_.emplace(plan_.at(next_), now_s);
  return *current_;
}

Reply Session::act(const Action& a, double now_s) {
  if (!current_) return Reply{"no round is running", false, false, false};
  Reply reply = current_->act(a, now_s);
  if (!reply.finished) return reply;
  const Round& round = current_->round();
  for (const EnvelopeResult& e : current_->results()) {
    ResultRow row;
    row.participant = spec_.participant;
    row.experiment = round.experiment;
    row.practice = round.practice;
    row.position = round.position;
    row.instrument = round.instrument;
    row.mapping = mapping_of_experiment(round.experiment);
    row.envelope = e.envelope;
    row.key = e.key;
    row.rank = e.rank;
    row.seconds_felt = e.seconds_felt;
    row.times_selected = e.times_selected;
    row.round_started = current_->started_s();
    row.ranked_at = e.ranked_at_s;
    row.round_ended = current_->ended_s();
    row.seed = spec_.seed;
    row.version = spec_.version;
    row.participant_data = spec_.participant_data;
    ready_.push_back(row);
  }
  if (round.practice) {
    reply.message = fmt::format("round done. The analogue envelope (the {}'s own) was key {}", round.instrument,
                                round.key_of(Envelope::analogue));
  }
  done_[next_] = true;
  current_.reset();
  skip_done();
  return reply;
}

std::vector<ResultRow> Session::take_rows() { return std::exchange(ready_, {}); }

std::optional<Action> action_for_key(char c) {
  switch (c) {
    case '0':
    case '1':
    case '2': return Action{Action::Kind::select, c - '0'};
    case 'a':
    case 'A': return Action{Action::Kind::rank, 0};
    case 'b':
    case 'B': return Action{Action::Kind::rank, 1};
    case 'c':
    case 'C': return Action{Action::Kind::rank, 2};
    case 'u':
    case 'U': return Action{Action::Kind::undo, 0};
    case '\r':
    case '\n':
    case 'n': return Action{Action::Kind::next, 0};
    default: return std::nullopt;
  }
}

}  // namespace hmp::study
