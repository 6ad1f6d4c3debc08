// The participant's data (host/study/participant.hpp): the options' and the file's values, the results
// file's last three columns (round trip; files from before them still read; a participant's rows must
// agree), resuming with other values refused, and the summary `hmp study analyze` prints.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "host/common/error.hpp"
#include "host/study/analysis.hpp"
#include "host/study/participant.hpp"
#include "host/study/results_csv.hpp"
#include "host/study/session.hpp"
#include "tests/host/study/results_error.hpp"
#include "tests/host/study/round_row.hpp"

namespace {

using namespace hmp::study;
using hmp::study::test::error_of;

const ParticipantTexts kOptions{"--age", "--sex", "--handedness"};

ParticipantData data(std::optional<int> age, std::optional<Sex> sex, std::optional<Handedness> hand) {
  return ParticipantData{age, sex, hand};
}

// One main round (experiment 1, `instrument`) of participant p: three rows, key k ranked k + 1.
std::vector<ResultRow> main_round(const std::string& p, const std::string& instrument, const ParticipantData& d) {
  std::vector<ResultRow> rows;
  for (int k = 0; k < 3; ++k) {
    ResultRow r = hmp::study::test::round_row(p, instrument, k, false, 7, "v");
    r.participant_data = d;
    rows.push_back(r);
  }
  return rows;
}

std::string csv(const std::vector<ResultRow>& rows) {
  std::string s = std::string(kResultsHeader) + "\n";
  for (const ResultRow& r : rows) s += format_row(r) + "\n";
  return s;
}

std::string message_of(const auto& action) {
  try {
    action();
  } catch (const hmp::BadInput& e) {
    return e.what();
  }
  return "";
}

TEST(ParticipantOptions, GoodValuesAndNothingGiven) {
  EXPECT_EQ(parse_participant({"34", "female", "left"}, kOptions, ""), data(34, Sex::female, Handedness::left));
  EXPECT_EQ(parse_participant({"5", "unstated", "ambidextrous"}, kOptions, ""),
            data(5, Sex::unstated, Handedness::ambidextrous));
  EXPECT_EQ(parse_participant({"120", "other", "unstated"}, kOptions, ""), data(120, Sex::other, Handedness::unstated));
  EXPECT_EQ(parse_participant({"", "", ""}, kOptions, ""), ParticipantData{});
  EXPECT_EQ(parse_participant({"", "male", ""}, kOptions, ""), data(std::nullopt, Sex::male, std::nullopt));
}

TEST(ParticipantOptions, BadValuesNameTheOptionAndWhatIsAllowed) {
  auto error = [](const ParticipantTexts& t) { return message_of([&] { parse_participant(t, kOptions, ""); }); };
  EXPECT_EQ(error({"4", "", ""}), "--age 4: whole years from 5 to 120");
  EXPECT_EQ(error({"121", "", ""}), "--age 121: whole years from 5 to 120");
  for (const char* age : {"-30", "+30", "30.5", "3e1", " 30", "30 ", "thirty", "99999999999"}) {
    EXPECT_EQ(error({age, "", ""}), std::string("--age ") + age + ": whole years from 5 to 120") << age;
  }
  EXPECT_EQ(error({"", "f", ""}), "--sex f: female, male, other or unstated");
  EXPECT_EQ(error({"", "Female", ""}), "--sex Female: female, male, other or unstated");
  EXPECT_EQ(error({"", "", "both"}), "--handedness both: left, right, ambidextrous or unstated");
  EXPECT_EQ(error({"", "", "\x1b[2J"}), "--handedness \\x1B[2J: left, right, ambidextrous or unstated");  // escaped
}

TEST(ParticipantColumns, RoundTripAtTheEndOfTheRow) {
  EXPECT_EQ(std::string(kResultsHeader), std::string(kResultsHeaderWithoutParticipant) + ",age,sex,handedness");
  const auto given = main_round("p1", "flute", data(34, Sex::female, Handedness::right));
  const auto none = main_round("p2", "flute", ParticipantData{});
  const auto some = main_round("p3", "flute", data(std::nullopt, Sex::unstated, std::nullopt));
  EXPECT_TRUE(format_row(given[0]).ends_with(",v,34,female,right")) << format_row(given[0]);
  EXPECT_TRUE(format_row(none[0]).ends_with(",v,,,")) << format_row(none[0]);
  EXPECT_TRUE(format_row(some[0]).ends_with(",v,,unstated,")) << format_row(some[0]);
  std::vector<ResultRow> all = given;
  all.insert(all.end(), none.begin(), none.end());
  all.insert(all.end(), some.begin(), some.end());
  const std::string text = csv(all);
  EXPECT_EQ(results_columns(text), Columns::with_participant);
  const auto back = parse_results(text, "r.csv");
  ASSERT_EQ(back.size(), 9u);
  EXPECT_EQ(back[0].participant_data, data(34, Sex::female, Handedness::right));
  EXPECT_EQ(back[3].participant_data, ParticipantData{});
  EXPECT_EQ(back[8].participant_data, data(std::nullopt, Sex::unstated, std::nullopt));
  for (std::size_t i = 0; i < all.size(); ++i) EXPECT_EQ(format_row(back[i]), format_row(all[i]));
}

// A file as the program wrote it before the participant's columns: 16 columns, read as before.
const std::string kOldFile =
    "participant,experiment,phase,position,instrument,mapping,envelope,key,rank,seconds_felt,times_selected,"
    "round_started_utc,ranked_utc,round_ended_utc,seed,version\n"
    "old,1,main,1,flute,paper,triangle,0,2,3.000,1,2026-01-01T10:00:00.000Z,2026-01-01T10:00:05.000Z,2026-01-01T10:00:"
    "09.000Z,4,hmp 0.1.0\n"
    "old,1,main,1,flute,paper,analogue,1,1,3.000,1,2026-01-01T10:00:00.000Z,2026-01-01T10:00:06.000Z,2026-01-01T10:00:"
    "09.000Z,4,hmp 0.1.0\n"
    "old,1,main,1,flute,paper,square,2,3,3.000,1,2026-01-01T10:00:00.000Z,2026-01-01T10:00:07.000Z,2026-01-01T10:00:09."
    "000Z,4,hmp 0.1.0\n";

TEST(ParticipantColumns, AFileWithTheOldHeaderStillParsesAndAnalyses) {
  EXPECT_EQ(results_columns(kOldFile), Columns::without_participant);
  EXPECT_EQ(results_columns("\xEF\xBB\xBF" + kOldFile), Columns::without_participant);
  EXPECT_EQ(results_columns(""), Columns::with_participant);  // a new file gets the new header
  const auto rows = parse_results(kOldFile, "old.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[1].envelope, Envelope::analogue);
  EXPECT_EQ(rows[1].rank, 1);
  EXPECT_EQ(rows[1].version, "hmp 0.1.0");
  EXPECT_EQ(rows[1].participant_data, ParticipantData{});
  const auto groups = analyze(rows);
  ASSERT_EQ(groups.size(), 1u);
  EXPECT_EQ(groups[0].first_votes[static_cast<std::size_t>(Envelope::analogue)], 1);
  EXPECT_EQ(format_summary(summarize(analysed_participants(rows))),
            "participants: 1 — sex: female 0, male 0, other 0, unstated 1\n"
            "age: not given (by none of the 1)\n"
            "handedness: left 0, right 0, ambidextrous 0, unstated 1\n");
  // Rows appended to it keep its layout; a row of the other layout does not fit.
  const std::string appended =
      kOldFile + format_row(main_round("new", "violin", {})[0], Columns::without_participant) + "\n";
  EXPECT_EQ(error_of(appended),
            "res.csv:5: participant new experiment 1 violin: 1 rows, a round has 3");  // 16 fields: read
  EXPECT_EQ(error_of(kOldFile + format_row(rows[0]) + "\n"), "res.csv:5: 19 fields, expected 16");
  EXPECT_EQ(error_of(csv(rows) + "old,1,main\n"), "res.csv:5: 3 fields, expected 19");
}

TEST(ParticipantColumns, BadValuesInTheFileNameFileAndLine) {
  auto with_fields = [](const std::string& fields) {
    std::string text = csv(main_round("p1", "flute", {}));
    const std::size_t second = text.find('\n', text.find('\n') + 1);  // the end of line 2
    return text.replace(second - 2, 2, fields);                       // the row ends "v,,,": age, sex, handedness empty
  };
  EXPECT_EQ(error_of(with_fields(",,")), "");
  EXPECT_EQ(error_of(with_fields("4,,")), "res.csv:2: age 4: whole years from 5 to 120");
  EXPECT_EQ(error_of(with_fields(",m,")), "res.csv:2: sex m: female, male, other or unstated");
  EXPECT_EQ(error_of(with_fields(",,lefty")), "res.csv:2: handedness lefty: left, right, ambidextrous or unstated");
}

TEST(ParticipantColumns, AParticipantsRowsMustAgree) {
  auto rows = main_round("p1", "flute", data(30, Sex::male, Handedness::right));
  const auto other = main_round("p2", "flute", data(50, Sex::female, Handedness::left));  // another person may differ
  rows.insert(rows.end(), other.begin(), other.end());
  ASSERT_EQ(error_of(csv(rows)), "");
  auto changed = [&](std::size_t i, const ParticipantData& d) {
    auto copy = rows;
    copy[i].participant_data = d;
    return error_of(csv(copy));
  };
  // Row i is on line i + 2; the first row of p1 is line 2.
  EXPECT_EQ(changed(2, data(31, Sex::male, Handedness::right)), "res.csv:4: participant p1: age 31, but 30 on line 2");
  EXPECT_EQ(changed(1, data(30, Sex::other, Handedness::right)),
            "res.csv:3: participant p1: sex other, but male on line 2");
  EXPECT_EQ(changed(2, data(30, Sex::male, std::nullopt)),
            "res.csv:4: participant p1: handedness (not given), but right on line 2");
  EXPECT_EQ(changed(0, data(std::nullopt, Sex::male, Handedness::right)),
            "res.csv:3: participant p1: age 30, but (not given) on line 2");
  EXPECT_EQ(changed(5, data(50, Sex::unstated, Handedness::left)),
            "res.csv:7: participant p2: sex unstated, but female on line 5");
}

TEST(ParticipantColumns, RowsInTwoFilesMustAgreeToo) {
  auto a = parse_results(csv(main_round("p1", "flute", data(30, Sex::male, std::nullopt))), "a.csv");
  const auto b = parse_results(csv(main_round("p1", "violin", data(30, Sex::female, std::nullopt))), "b.csv");
  ASSERT_EQ(analysed_participants(a).size(), 1u);
  a.insert(a.end(), b.begin(), b.end());
  EXPECT_EQ(message_of([&] { analysed_participants(a); }), "b.csv:2: participant p1: sex female, but male on a.csv:2");
}

TEST(ParticipantSummaryText, TheNumbersOfAConstructedFile) {
  // Four analysed participants: ages 30, 22, —, 41 (mean 93 / 3 = 31.0); sex female, male, unstated and
  // not given (both unstated); handedness right, left, right, ambidextrous. A fifth with practice rows
  // only is not analysed, so not counted.
  const std::vector<std::pair<std::string, ParticipantData>> people{
      {"a", data(30, Sex::female, Handedness::right)},
      {"b", data(22, Sex::male, Handedness::left)},
      {"c", data(std::nullopt, Sex::unstated, Handedness::right)},
      {"d", data(41, std::nullopt, Handedness::ambidextrous)}};
  std::vector<ResultRow> rows;
  for (const auto& [id, d] : people) {
    for (const char* instrument : {"flute", "violin"}) {
      for (const ResultRow& r : main_round(id, instrument, d)) rows.push_back(r);
    }
  }
  for (ResultRow r : main_round("e", "violin", data(99, Sex::other, Handedness::left))) {
    r.practice = true;
    rows.push_back(r);
  }
  const auto parsed = parse_results(csv(rows), "r.csv");
  const ParticipantSummary s = summarize(analysed_participants(parsed));
  EXPECT_EQ(s.participants, 4);
  EXPECT_EQ(s.by_sex, (std::array<int, 4>{1, 1, 0, 2}));
  EXPECT_EQ(s.by_handedness, (std::array<int, 4>{1, 2, 1, 0}));
  EXPECT_EQ(s.with_age, 3);
  EXPECT_EQ(s.age_min, 22);
  EXPECT_EQ(s.age_max, 41);
  EXPECT_DOUBLE_EQ(s.age_mean, 31.0);
  EXPECT_EQ(format_summary(s),
            "participants: 4 — sex: female 1, male 1, other 0, unstated 2\n"
            "age: 22–41 years, mean 31.0 (3 gave it; 1 did not)\n"
            "handedness: left 1, right 2, ambidextrous 1, unstated 0\n");
  // All with an age: said so. The mean is over those with an age: (30 + 35) / 2, (20 + 20 + 25) / 3.
  EXPECT_EQ(format_summary(summarize({data(30, Sex::male, std::nullopt), data(35, Sex::male, std::nullopt)})),
            "participants: 2 — sex: female 0, male 2, other 0, unstated 0\n"
            "age: 30–35 years, mean 32.5 (all 2 gave it)\n"
            "handedness: left 0, right 0, ambidextrous 0, unstated 2\n");
  EXPECT_DOUBLE_EQ(summarize({data(20, {}, {}), data(20, {}, {}), data(25, {}, {})}).age_mean, 65.0 / 3);
}

// Plays the whole session: each round ranked key k → letter k.
std::vector<ResultRow> play(Session& s) {
  std::vector<ResultRow> rows;
  double t = 1.8e9;
  while (!s.done()) {
    s.begin_round(t);
    for (int k = 0; k < 3; ++k) {
      s.act({Action::Kind::select, k}, t += 1);
      s.act({Action::Kind::rank, k}, t += 1);
    }
    s.act({Action::Kind::next, 0}, t += 1);
    for (const ResultRow& r : s.take_rows()) rows.push_back(r);
  }
  return rows;
}

TEST(ParticipantSession, RowsCarryTheDataAndResumingKeepsIt) {
  Session first({"p1", 5, {1}, "v", data(28, Sex::female, std::nullopt)}, {});
  std::vector<ResultRow> rows = play(first);
  ASSERT_EQ(rows.size(), 18u);
  for (const ResultRow& r : rows) EXPECT_EQ(r.participant_data, data(28, Sex::female, std::nullopt));
  rows.resize(6);  // the practice rounds only: the rest is still to do
  const auto file = parse_results(csv(rows), "r.csv");

  // Nothing given again: the recorded data goes on. The same given again: fine.
  Session quiet({"p1", 5, {1}, "v", {}}, file);
  EXPECT_EQ(quiet.participant_data(), data(28, Sex::female, std::nullopt));
  for (const ResultRow& r : play(quiet)) EXPECT_EQ(r.participant_data, data(28, Sex::female, std::nullopt));
  Session same({"p1", 5, {1}, "v", data(28, std::nullopt, std::nullopt)}, file);
  EXPECT_EQ(same.participant_data(), data(28, Sex::female, std::nullopt));

  // Another value, or one the rows do not have: refused, naming the field, both values and the row.
  auto resumed_with = [&](const ParticipantData& d) {
    return message_of([&] { Session s({"p1", 5, {1}, "v", d}, file); });
  };
  EXPECT_EQ(
      resumed_with(data(29, std::nullopt, std::nullopt)),
      "participant p1: age 29, but 28 on r.csv:2 (a participant's rows must agree; leave the option out to keep it)");
  EXPECT_EQ(resumed_with(data(std::nullopt, Sex::male, std::nullopt)),
            "participant p1: sex male, but female on r.csv:2 (a participant's rows must agree; leave the option out to "
            "keep it)");
  EXPECT_EQ(
      resumed_with(data(std::nullopt, std::nullopt, Handedness::left)),
      "participant p1: handedness left, but (not given) on r.csv:2 (a participant's rows must agree; leave the option "
      "out to keep it)");
  // Another participant is not bound by p1's data.
  Session other({"p2", 5, {1}, "v", data(60, Sex::male, Handedness::left)}, file);
  EXPECT_EQ(other.participant_data(), data(60, Sex::male, Handedness::left));
}

}  // namespace
