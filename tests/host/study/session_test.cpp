// The study's session logic (host/study/): the seeded plan, one round's keys and ranking, the session's
// rows and resume, and the results file's rows (round trip; bad rows → file:line errors).
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>

#include <fmt/format.h>

#include "host/common/error.hpp"
#include "host/study/analysis.hpp"
#include "host/study/results_csv.hpp"
#include "host/study/session.hpp"
#include "tests/host/study/results_error.hpp"

namespace {

using namespace hmp::study;
using hmp::study::test::error_of;

std::string plan_text(const std::vector<Round>& plan) {
  std::string s;
  for (const Round& r : plan) {
    s += r.instrument + ":";
    for (const Envelope e : r.by_key) s += envelope_name(e), s += ",";
    s += ";";
  }
  return s;
}

TEST(StudyPlan, ShapeOfABothExperimentsSession) {
  const auto plan = make_plan("p01", 42, {1, 2});
  ASSERT_EQ(plan.size(), 2u + 8u);
  EXPECT_TRUE(plan[0].practice && plan[1].practice);
  EXPECT_EQ(plan[0].instrument, "violin");
  EXPECT_EQ(plan[1].instrument, "contrabass");
  for (int experiment : {1, 2}) {
    std::multiset<std::string> seen;
    for (const Round& r : plan) {
      if (!r.practice && r.experiment == experiment) seen.insert(r.instrument);
    }
    EXPECT_EQ(seen, (std::multiset<std::string>{"contrabass", "flute", "harpsichord", "violin"}));
  }
  for (const Round& r : plan) {
    std::set<Envelope> keys(r.by_key.begin(), r.by_key.end());
    EXPECT_EQ(keys.size(), 3u);
  }
  EXPECT_EQ(make_plan("p01", 42, {2}).size(), 6u);
  EXPECT_EQ(make_plan("p01", 42, {2})[0].experiment, 2);  // practice with the session's mapping
}

TEST(StudyPlan, SeededOrderIsReproducibleAndParticipantsDiffer) {
  EXPECT_EQ(plan_text(make_plan("anna", 7, {1, 2})), plan_text(make_plan("anna", 7, {1, 2})));
  EXPECT_NE(plan_text(make_plan("anna", 7, {1, 2})), plan_text(make_plan("bert", 7, {1, 2})));
  EXPECT_NE(plan_text(make_plan("anna", 7, {1, 2})), plan_text(make_plan("anna", 8, {1, 2})));
  std::set<std::string> plans;
  for (int p = 0; p < 200; ++p) plans.insert(plan_text(make_plan("p" + std::to_string(p), 1, {1, 2})));
  EXPECT_EQ(plans.size(), 200u);  // 24^2·6^10 possible orders: 200 participants never collide in practice
}

TEST(StudyPlan, OrdersAreUniform) {
  // Over 12,000 rounds each of the 6 envelope orders and each instrument in each place turns up about
  // equally often (bounds: ±6 standard deviations of a binomial).
  std::map<std::string, int> orders;
  std::map<std::pair<int, std::string>, int> places;
  int rounds = 0;
  for (int p = 0; p < 1500; ++p) {
    for (const Round& r : make_plan("u" + std::to_string(p), 99, {1, 2})) {
      if (r.practice) continue;
      ++rounds;
      std::string o;
      for (const Envelope e : r.by_key) o += envelope_name(e)[0];
      ++orders[o];
      ++places[{r.position, r.instrument}];
    }
  }
  ASSERT_EQ(orders.size(), 6u);
  for (const auto& [o, n] : orders) EXPECT_NEAR(n, rounds / 6.0, 6 * std::sqrt(rounds * (1 / 6.0) * (5 / 6.0))) << o;
  ASSERT_EQ(places.size(), 16u);
  for (const auto& [pl, n] : places) EXPECT_NEAR(n, rounds / 16.0, 6 * std::sqrt(rounds / 16.0 * (15 / 16.0)));
}

Round square_triangle_analogue() {
  Round r;
  r.instrument = "flute";
  r.position = 1;
  r.by_key = {Envelope::square, Envelope::triangle, Envelope::analogue};
  return r;
}

Action sel(int k) { return {Action::Kind::select, k}; }
Action rank(int letter) { return {Action::Kind::rank, letter}; }
const Action kUndo{Action::Kind::undo, 0};
const Action kNext{Action::Kind::next, 0};

TEST(StudyRound, RanksEachLetterOnceUndoAndNoGoingOnBeforeAllRanked) {
  RoundState r(square_triangle_analogue(), 100.0);
  EXPECT_FALSE(r.act(kNext, 101).accepted);
  EXPECT_TRUE(r.act(rank(1), 102).accepted);   // key 0 → B
  EXPECT_FALSE(r.act(rank(0), 103).accepted);  // key 0 already ranked
  EXPECT_TRUE(r.act(sel(1), 104).envelope_changed);
  EXPECT_FALSE(r.act(sel(1), 104.5).envelope_changed);  // the same key again: nothing to switch
  EXPECT_FALSE(r.act(rank(1), 105).accepted);           // B is taken
  EXPECT_TRUE(r.act(rank(0), 106).accepted);            // key 1 → A
  EXPECT_TRUE(r.act(kUndo, 107).accepted);              // takes back key 1's A
  EXPECT_FALSE(r.rank_of_key(1).has_value());
  EXPECT_TRUE(r.act(rank(2), 108).accepted);  // key 1 → C
  EXPECT_FALSE(r.act(kNext, 109).accepted);
  EXPECT_FALSE(r.act(sel(3), 110).accepted);
  EXPECT_TRUE(r.act(sel(2), 110).accepted);
  EXPECT_TRUE(r.act(rank(0), 111).accepted);  // key 2 → A
  const Reply done = r.act(kNext, 115);
  EXPECT_TRUE(done.finished);
  EXPECT_FALSE(r.act(sel(0), 116).accepted);
  const auto results = r.results();
  ASSERT_EQ(results.size(), 3u);
  EXPECT_EQ(results[0].rank, 2);
  EXPECT_EQ(results[1].rank, 3);
  EXPECT_EQ(results[2].rank, 1);
  // Felt: key 0 from 100 to 104 (4 s), key 1 from 104 to 110 (6 s), key 2 from 110 to 115 (5 s).
  EXPECT_DOUBLE_EQ(results[0].seconds_felt, 4.0);
  EXPECT_DOUBLE_EQ(results[1].seconds_felt, 6.0);
  EXPECT_DOUBLE_EQ(results[2].seconds_felt, 5.0);
  EXPECT_EQ(results[0].times_selected, 1);
  EXPECT_EQ(results[1].times_selected, 1);
  EXPECT_EQ(results[2].times_selected, 1);
  EXPECT_DOUBLE_EQ(results[1].ranked_at_s, 108.0);  // the undone rank's time is not kept
  EXPECT_EQ(r.act(kUndo, 117).accepted, false);
}

TEST(StudyRound, UndoWithNothingRankedAndKeyMap) {
  RoundState r(square_triangle_analogue(), 0);
  EXPECT_FALSE(r.act(kUndo, 1).accepted);
  EXPECT_EQ(action_for_key('1')->kind, Action::Kind::select);
  EXPECT_EQ(action_for_key('C')->value, 2);
  EXPECT_EQ(action_for_key('\r')->kind, Action::Kind::next);
  EXPECT_EQ(action_for_key('u')->kind, Action::Kind::undo);
  EXPECT_FALSE(action_for_key('3').has_value());
  EXPECT_FALSE(action_for_key('\x1b').has_value());
}

// Plays a whole session: in every round, rank the envelope under key k with letter (k + shift) % 3.
std::vector<ResultRow> play(Session& s, double t0, int shift, std::size_t max_rounds = 100) {
  std::vector<ResultRow> rows;
  double t = t0;
  for (std::size_t n = 0; n < max_rounds && !s.done(); ++n) {
    s.begin_round(t);
    for (int k = 0; k < 3; ++k) {
      s.act(sel(k), t += 1);
      s.act(rank((k + shift) % 3), t += 1);
    }
    const Reply reply = s.act(kNext, t += 1);
    EXPECT_TRUE(reply.finished);
    for (ResultRow& r : s.take_rows()) rows.push_back(r);
  }
  return rows;
}

std::string csv(const std::vector<ResultRow>& rows) {
  std::string s = std::string(kResultsHeader) + "\n";
  for (const ResultRow& r : rows) s += format_row(r) + "\n";
  return s;
}

TEST(StudySession, WholeSessionGivesTwoByFourByThreeRowsPlusPractice) {
  Session s({"p1", 5, {1, 2}, "test", {}}, {});
  const auto rows = play(s, 1.8e9, 0);
  ASSERT_EQ(rows.size(), 2u * 4u * 3u + 6u);
  EXPECT_EQ(std::count_if(rows.begin(), rows.end(), [](const ResultRow& r) { return r.practice; }), 6);
  for (const ResultRow& r : rows) {
    EXPECT_EQ(r.rank, r.key + 1);  // shift 0: key k got letter k
    EXPECT_EQ(r.seed, 5u);
    EXPECT_EQ(r.mapping, r.experiment == 1 ? "paper" : "constant");
  }
  // The text written is read back the same (times at millisecond precision).
  const auto back = parse_results(csv(rows), "r.csv");
  ASSERT_EQ(back.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(format_row(back[i]), format_row(rows[i]));
    EXPECT_EQ(back[i].line, static_cast<int>(i) + 2);
  }
}

TEST(StudySession, PracticeRevealsTheAnalogueKey) {
  Session s({"p1", 5, {1}, "test", {}}, {});
  const Round first = s.plan()[0];
  s.begin_round(0);
  for (int k = 0; k < 3; ++k) s.act(sel(k), 1), s.act(rank(k), 1);
  const Reply r = s.act(kNext, 2);
  EXPECT_NE(r.message.find("key " + std::to_string(first.key_of(Envelope::analogue))), std::string::npos) << r.message;
}

TEST(StudySession, ResumesAfterTheRoundsAlreadyWritten) {
  Session first({"p1", 5, {1, 2}, "test", {}}, {});
  const auto part = play(first, 1.8e9, 1, 4);  // practice + 2 rounds
  ASSERT_EQ(part.size(), 12u);
  Session other({"p2", 5, {1, 2}, "test", {}}, {});
  const auto someone_else = play(other, 1.8e9, 2);
  std::vector<ResultRow> file = part;
  file.insert(file.end(), someone_else.begin(), someone_else.end());

  Session resumed({"p1", 5, {1, 2}, "test", {}}, parse_results(csv(file), "r.csv"));
  EXPECT_EQ(resumed.rounds_done(), 4u);
  const auto rest = play(resumed, 1.9e9, 1);
  EXPECT_EQ(rest.size(), 18u);
  std::vector<ResultRow> all = part;
  all.insert(all.end(), rest.begin(), rest.end());
  std::set<std::tuple<int, bool, std::string>> rounds;
  for (const ResultRow& r : all) rounds.insert({r.experiment, r.practice, r.instrument});
  EXPECT_EQ(rounds.size(), 10u);  // each round once
  // The plan after resuming is the same as without the interruption.
  Session straight({"p1", 5, {1, 2}, "test", {}}, {});
  EXPECT_EQ(plan_text(straight.plan()), plan_text(resumed.plan()));

  // Rows of the same participant with another seed: refused, saying which seed to use.
  try {
    Session wrong({"p1", 6, {1, 2}, "test", {}}, parse_results(csv(file), "r.csv"));
    FAIL() << "no error";
  } catch (const hmp::BadInput& e) {
    EXPECT_NE(std::string(e.what()).find("--seed 5"), std::string::npos) << e.what();
  }
}

TEST(StudyResultsFile, BadRowsNameFileAndLine) {
  Session s({"p1", 5, {1}, "v", {}}, {});
  const auto rows = play(s, 1.8e9, 0);
  const std::string good = csv(rows);
  ASSERT_EQ(error_of(good), "");
  auto with_line = [&](int line, const std::string& replacement) {
    std::vector<std::string> lines;
    std::string cur;
    for (char c : good) {
      if (c == '\n')
        lines.push_back(cur), cur.clear();
      else
        cur += c;
    }
    lines[static_cast<std::size_t>(line - 1)] = replacement;
    std::string out;
    for (const auto& l : lines) out += l + "\n";
    return out;
  };
  auto replace = [&](int line, const std::string& from, const std::string& to) {
    ResultRow r = rows[static_cast<std::size_t>(line - 2)];
    std::string text = format_row(r);
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos);
    text.replace(at, from.size(), to);
    return with_line(line, text);
  };
  EXPECT_EQ(error_of("participant,oops\n"), "res.csv:1: not a study results file (the header differs)");
  EXPECT_NE(error_of(replace(9, ",square,", ",sawtooth,")).find("res.csv:9: unknown envelope \"sawtooth\""),
            std::string::npos);
  // The row of line 9 takes another rank of its round: that rank is now used twice.
  {
    const ResultRow& r = rows[7];
    const int other_rank = r.rank == 1 ? 2 : 1;
    ResultRow changed = r;
    changed.rank = other_rank;
    const std::string e = error_of(with_line(9, format_row(changed)));
    EXPECT_NE(e.find("res.csv:"), std::string::npos) << e;
    EXPECT_NE(e.find("rank " + std::to_string(other_rank) + " used twice"), std::string::npos) << e;
  }
  EXPECT_NE(error_of(with_line(5, "p1,1,main")).find("res.csv:5: 3 fields, expected 19"), std::string::npos);
  EXPECT_NE(error_of(replace(6, ",paper,", ",constant,")).find("res.csv:6: mapping"), std::string::npos);
  EXPECT_NE(error_of(replace(6, "p1,", "p 1,")).find("res.csv:6: bad participant id"), std::string::npos);
  EXPECT_NE(error_of(replace(6, ",5,v", ",-5,v")).find("res.csv:6: seed"), std::string::npos);
  EXPECT_NE(error_of(replace(6, ",5,v", ",99999999999999999999999,v")).find("res.csv:6: seed"), std::string::npos);
  EXPECT_NE(error_of(replace(6, "Z,", "X,")).find("res.csv:6: round_started_utc"), std::string::npos);
  // A round cut short (its last row missing).
  std::string cut = good.substr(0, good.rfind('\n', good.size() - 2) + 1);
  EXPECT_NE(error_of(cut).find("2 rows, a round has 3"), std::string::npos) << error_of(cut);
  // Hostile numbers in seconds_felt.
  for (const char* bad : {"nan", "inf", "-1", "1e999", "", "0x10"}) {
    ResultRow r = rows[0];
    std::string text = format_row(r);
    const std::string felt = fmt::format(",{:.3f},", r.seconds_felt);
    text.replace(text.find(felt), felt.size(), std::string(",") + bad + ",");
    EXPECT_NE(error_of(with_line(2, text)).find("res.csv:2: seconds_felt"), std::string::npos) << bad;
  }
  EXPECT_EQ(parse_results("", "e.csv").size(), 0u);
}

TEST(StudyAnalysis, GroupsAndDuplicateFiles) {
  std::vector<ResultRow> all;
  for (const char* p : {"a", "b", "c"}) {
    Session s({p, 3, {1, 2}, "v", {}}, {});
    for (const ResultRow& r : play(s, 1.8e9, 0)) all.push_back(r);
  }
  const auto groups = analyze(all);
  ASSERT_EQ(groups.size(), 8u);
  for (const GroupAnalysis& g : groups) EXPECT_EQ(g.participants, 3);
  EXPECT_EQ(groups[0].experiment, 1);
  EXPECT_EQ(groups[0].instrument, "flute");
  EXPECT_EQ(groups[7].experiment, 2);
  EXPECT_EQ(groups[7].instrument, "harpsichord");
  auto twice = all;
  for (ResultRow& r : all) r.file = "second.csv", r.line = 7;
  twice.insert(twice.end(), all.begin(), all.end());
  try {
    analyze(twice);
    ADD_FAILURE() << "no error";
  } catch (const hmp::BadInput& e) {
    EXPECT_EQ(std::string(e.what()).rfind("second.csv:7: participant a has experiment 1", 0), 0u) << e.what();
  }
}

}  // namespace
