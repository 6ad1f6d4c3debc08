#include "host/study/round.hpp"

#include <algorithm>
#include <utility>

#include <fmt/format.h>

namespace hmp::study {

char rank_letter(int rank_index) { return static_cast<char>('A' + rank_index); }

RoundState::RoundState(Round round, double now_s) : round_(std::move(round)), started_s_(now_s), since_s_(now_s) {
  selected_count_[0] = 1;
}

void RoundState::account(double now_s) {
  if (now_s > since_s_) felt_[static_cast<std::size_t>(selected_)] += now_s - since_s_;
  since_s_ = std::max(since_s_, now_s);
}

Reply RoundState::act(const Action& a, double now_s) {
  Reply r;
  if (finished_) {
    r.message = "this round is over";
    return r;
  }
  account(now_s);
  switch (a.kind) {
    case Action::Kind::select: {
      if (a.value < 0 || a.value > 2) {
        r.message = "keys 0, 1 and 2 choose the envelope";
        return r;
      }
      r.accepted = true;
      if (a.value != selected_) {
        selected_ = a.value;
        ++selected_count_[static_cast<std::size_t>(selected_)];
        r.envelope_changed = true;
      }
      r.message = fmt::format("now feeling key {}", selected_);
      return r;
    }
    case Action::Kind::rank: {
      const auto key = static_cast<std::size_t>(selected_);
      if (a.value < 0 || a.value > 2) {
        r.message = "ranks are A, B and C";
        return r;
      }
      if (ranks_[key]) {
        r.message =
            fmt::format("key {} already has rank {} (u undoes the last rank)", selected_, rank_letter(*ranks_[key]));
        return r;
      }
      for (int k = 0; k < 3; ++k) {
        if (ranks_[static_cast<std::size_t>(k)] == a.value) {
          r.message =
              fmt::format("rank {} is already given to key {} (u undoes the last rank)", rank_letter(a.value), k);
          return r;
        }
      }
      ranks_[key] = a.value;
      ranked_at_[key] = now_s;
      rank_history_.push_back(selected_);
      r.accepted = true;
      r.message = fmt::format("key {} ranked {}", selected_, rank_letter(a.value));
      return r;
    }
    case Action::Kind::undo: {
      if (rank_history_.empty()) {
        r.message = "nothing to undo";
        return r;
      }
      const int key = rank_history_.back();
      rank_history_.pop_back();
      r.message = fmt::format("rank {} of key {} undone", rank_letter(*ranks_[static_cast<std::size_t>(key)]), key);
      ranks_[static_cast<std::size_t>(key)].reset();
      r.accepted = true;
      return r;
    }
    case Action::Kind::next: {
      if (rank_history_.size() < 3) {
        r.message = fmt::format("rank all three envelopes first ({} of 3 ranked)", rank_history_.size());
        return r;
      }
      finished_ = true;
      ended_s_ = now_s;
      r.accepted = true;
      r.finished = true;
      r.message = "round done";
      return r;
    }
  }
  return r;
}

std::vector<EnvelopeResult> RoundState::results() const {
  std::vector<EnvelopeResult> out;
  for (std::size_t k = 0; k < 3; ++k) {
    EnvelopeResult e;
    e.envelope = round_.by_key[k];
    e.key = static_cast<int>(k);
    e.rank = ranks_[k] ? *ranks_[k] + 1 : 0;
    e.seconds_felt = felt_[k];
    e.times_selected = selected_count_[k];
    e.ranked_at_s = ranked_at_[k];
    out.push_back(e);
  }
  return out;
}

std::string RoundState::prompt() const {
  std::string keys;
  for (int k = 0; k < 3; ++k) {
    const auto& rank = ranks_[static_cast<std::size_t>(k)];
    keys += fmt::format("{}[{}]{}{}", k == selected_ ? ">" : " ", k, rank ? std::string(1, rank_letter(*rank)) : "-",
                        k < 2 ? "  " : "");
  }
  const char* todo = rank_history_.size() < 3 ? "0/1/2 switch, a/b/c rank the one you feel (A best), u undo"
                                              : "all ranked: Enter to go on, u undo";
  return fmt::format("{}  |  {}", keys, todo);
}

}  // namespace hmp::study
