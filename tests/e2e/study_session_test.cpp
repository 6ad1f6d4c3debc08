// `hmp study` end to end (design §15): scripted participants type through the same key path as a person
// (stdin; a pipe instead of a terminal) on the simulated device without audio. Whole sessions for both
// experiments give exactly 2 × 4 × 3 rows + 6 practice rows each; a session killed (SIGKILL) mid-way
// and one whose input ends resume where they stopped, without touching the rows already written; the
// analysis of the pilot names the winners the scripts chose.
#include <gtest/gtest.h>

#include <algorithm>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "host/study/plan.hpp"
#include "tests/support/midi_builder.hpp"
#include "play_harness.hpp"
#include "study_keys.hpp"

namespace {

namespace fs = std::filesystem;
namespace test = hmp::test;
using hmp::study::Envelope;
using hmp::test::kAnalogueFirst;
using hmp::test::kTriangleFirst;
using hmp::test::session_keys;
// Checks, from a scripted run's stderr, that after every switch the player plays what the plan has under
// that key: the last player notice before the study's next line names the round's track, envelope and
// mapping ("auto" is the player's name of the analogue envelope).
void expect_switches_follow_plan(const std::string& err, const std::vector<hmp::study::Round>& plan) {
  std::istringstream in(err);
  int round = -1, switches = 0;
  std::string expected, last_notice;
  auto check = [&] {
    if (expected.empty()) return;
    EXPECT_NE(last_notice.find(expected), std::string::npos)
        << "expected " << expected << ", player said: " << last_notice;
    ++switches;
    expected.clear();
  };
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("player: ", 0) == 0) {
      last_notice = line;
    } else if (line.rfind("study: round", 0) == 0) {
      check();
      ++round;
    } else if (line.rfind("study: key ", 0) == 0) {
      check();
      last_notice.clear();
      const hmp::study::Round& r = plan.at(static_cast<std::size_t>(round));
      const Envelope e = r.by_key.at(static_cast<std::size_t>(std::stoi(line.substr(11))));
      expected = fmt::format("envelope {}, mapping {}", e == Envelope::analogue ? "auto" : hmp::study::envelope_name(e),
                             hmp::study::mapping_of_experiment(r.experiment));
    }
  }
  check();
  EXPECT_EQ(round + 1, static_cast<int>(plan.size()));
  EXPECT_EQ(switches, 2 * static_cast<int>(plan.size()));  // keys 1 and 2 of every round
}

class StudyE2e : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hmp-study-e2e-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string results() const { return slurp(dir_ / "study-results.csv"); }
  static std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  std::size_t rows_of(const std::string& participant) const {
    std::size_t n = 0;
    std::istringstream in(results());
    for (std::string line; std::getline(in, line);) n += line.rfind(participant + ",", 0) == 0 ? 1 : 0;
    return n;
  }
  test::CommandResult study(const std::string& participant, std::uint64_t seed, const std::string& keys) {
    const fs::path keys_file = dir_ / ("keys-" + participant);
    std::ofstream(keys_file) << keys;
    return test::run_command(test::kHmp + " study --participant " + participant + " --seed " + std::to_string(seed) +
                             " --device sim --no-audio --no-view --out '" + dir_.string() + "' < '" +
                             keys_file.string() + "'");
  }
  fs::path dir_;
};

TEST_F(StudyE2e, TwoParticipantPilotAndItsAnalysis) {
  const auto a = study("anna", 11, session_keys("anna", 11, 0, 10, kAnalogueFirst, kAnalogueFirst));
  ASSERT_EQ(a.status, 0) << a.err;
  expect_switches_follow_plan(a.err, hmp::study::make_plan("anna", 11, {1, 2}));
  // Practice comes from another piece (BWV 1079's Largo: violin track 2, contrabass track 3), the main
  // rounds from the demo, as in the paper.
  int practice = 0, main = 0;
  std::istringstream lines(a.err);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("study: round practice", 0) == 0) {
      ++practice;
      EXPECT_NE(line.find("bach-bwv1079-trio-sonata-largo.mid"), std::string::npos) << line;
      EXPECT_NE(line.find(line.find("violin") != std::string::npos ? "(track 2 of" : "(track 3 of"), std::string::npos)
          << line;
    } else if (line.rfind("study: round main", 0) == 0) {
      ++main;
      EXPECT_NE(line.find("bach-bwv1050-brandenburg5"), std::string::npos) << line;
    }
  }
  EXPECT_EQ(practice, 2);
  EXPECT_EQ(main, 8);
  const auto b = study("bert", 11, session_keys("bert", 11, 0, 10, kAnalogueFirst, kTriangleFirst));
  ASSERT_EQ(b.status, 0) << b.err;
  EXPECT_EQ(rows_of("anna"), 2u * 4u * 3u + 6u);
  EXPECT_EQ(rows_of("bert"), 2u * 4u * 3u + 6u);
  // Done participants are not asked again; nothing is appended.
  const std::string before = results();
  const auto again = study("anna", 11, "");
  EXPECT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(results(), before);

  const auto report = test::run_command(test::kHmp + " study analyze '" + (dir_ / "study-results.csv").string() +
                                        "' --json --out '" + (dir_ / "fig.png").string() + "'");
  ASSERT_EQ(report.status, 0) << report.err;
  const auto json = nlohmann::json::parse(report.out);
  ASSERT_EQ(json.size(), 8u);
  for (const auto& g : json) {
    EXPECT_EQ(g["participants"], 2);
    if (g["experiment"] == 1) {
      // Both rank analogue, triangle, square: full agreement.
      EXPECT_EQ(g["copeland_winners"], nlohmann::json::array({"analogue"}));
      EXPECT_EQ(g["envelopes"]["analogue"]["first_place_votes"], 2);
      EXPECT_NEAR(g["kendall_w"].get<double>(), 1.0, 1e-12);
      EXPECT_NEAR(g["friedman"]["chi2"].get<double>(), 4.0, 1e-12);
    } else {
      // Analogue and triangle split 1:1 and both beat square: a tie, stated.
      EXPECT_EQ(g["copeland_winners"], nlohmann::json::array({"triangle", "analogue"}));
      EXPECT_EQ(g["copeland_tie"], true);
      EXPECT_EQ(g["envelopes"]["square"]["copeland_score"], -2);
      EXPECT_EQ(g["envelopes"]["triangle"]["preferred_over"]["square"], 2);
    }
  }
  EXPECT_GT(fs::file_size(dir_ / "fig.png"), 1000u);
  const auto text = test::run_command(test::kHmp + " study analyze '" + (dir_ / "study-results.csv").string() + "'");
  EXPECT_NE(text.out.find("Copeland winner: triangle = analogue (tie of 2)"), std::string::npos) << text.out;
}

TEST_F(StudyE2e, ResumesAfterAKillAndAfterInputEnds) {
  const std::string all = session_keys("carl", 3, 0, 10, kAnalogueFirst, kTriangleFirst);
  const std::string first_part =
      session_keys("carl", 3, 0, 4, kAnalogueFirst, kTriangleFirst) + "01a";  // + half a round
  // Run with the keys on a pipe that stays open, as a person still at the keyboard; kill once the
  // four rounds' rows are written.
  const auto [pid, keyboard] =
      test::start_hmp_with_keyboard({"study", "--participant", "carl", "--seed", "3", "--device", "sim", "--no-audio",
                                     "--no-view", "--out", dir_.string()});
  ASSERT_GT(pid, 0);
  ASSERT_EQ(::write(keyboard, first_part.data(), first_part.size()), static_cast<ssize_t>(first_part.size()));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (rows_of("carl") < 12 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // it is in round 5 now, waiting for keys
  ::kill(pid, SIGKILL);
  ::waitpid(pid, nullptr, 0);
  ::close(keyboard);
  ASSERT_EQ(rows_of("carl"), 12u);
  const std::string written = results();

  // Input that ends mid-round: the session stops like on Ctrl-C (exit 130), the finished rounds kept.
  const auto partial = study("carl", 3, session_keys("carl", 3, 4, 6, kAnalogueFirst, kTriangleFirst) + "0");
  EXPECT_EQ(partial.status, 130) << partial.err;
  EXPECT_NE(partial.err.find("resume"), std::string::npos) << partial.err;
  EXPECT_EQ(rows_of("carl"), 18u);
  EXPECT_EQ(results().substr(0, written.size()), written);  // appended, never rewritten

  // Another seed for the same participant: refused (exit 2), nothing written.
  const auto wrong = study("carl", 4, "");
  EXPECT_EQ(wrong.status, 2);
  EXPECT_NE(wrong.err.find("seed 3"), std::string::npos) << wrong.err;

  const auto rest = study("carl", 3, session_keys("carl", 3, 6, 10, kAnalogueFirst, kTriangleFirst));
  ASSERT_EQ(rest.status, 0) << rest.err;
  EXPECT_EQ(rows_of("carl"), 30u);
  EXPECT_EQ(results().substr(0, written.size()), written);
  // The same rows as one uninterrupted run gives (ranks per round and envelope).
  const auto straight = study("dora", 3, all);
  ASSERT_EQ(straight.status, 0) << straight.err;
  const auto report =
      test::run_command(test::kHmp + " study analyze '" + (dir_ / "study-results.csv").string() + "' --json");
  ASSERT_EQ(report.status, 0) << report.err;
  EXPECT_EQ(nlohmann::json::parse(report.out).size(), 8u);
}

TEST_F(StudyE2e, TheSongLoopsUntilTheRoundIsRanked) {
  // A one-second song with the four instruments (GM programs) on tracks of their names.
  std::vector<midi_test::Events> tracks;
  const std::pair<const char*, int> instruments[] = {
      {"flute", 73}, {"violin", 40}, {"contrabass", 43}, {"harpsichord", 6}};
  for (int ch = 0; ch < 4; ++ch) {
    midi_test::Events e;
    e.name(0, instruments[ch].first).program(0, ch, instruments[ch].second);
    e.on(0, ch, 60 + ch).off(480, ch, 60 + ch).on(0, ch, 64 + ch).off(480, ch, 64 + ch).end();
    tracks.push_back(e);
  }
  const midi_test::Bytes bytes = midi_test::smf(1, 480, tracks);
  const fs::path song = dir_ / "short.mid";
  std::ofstream(song, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));

  const auto [pid, keyboard] = test::start_hmp_with_keyboard(
      {"study", "--participant", "loop", "--seed", "1", "--experiment", "1", "--song", song.string(), "--device", "sim",
       "--no-audio", "--no-view", "--out", dir_.string()});
  ASSERT_GT(pid, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(3500));  // three times the song on key 0
  const std::string keys = "a1b2c\n";
  ASSERT_EQ(::write(keyboard, keys.data(), keys.size()), static_cast<ssize_t>(keys.size()));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (rows_of("loop") < 3 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ::close(keyboard);  // input ends: the session stops, resumable
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 130) << status;
  ASSERT_EQ(rows_of("loop"), 3u);
  std::istringstream rows(results());
  std::string line;
  std::string header;
  std::getline(rows, header);
  std::getline(rows, line);  // key 0's row
  ASSERT_EQ(std::count(line.begin(), line.end(), ','), std::count(header.begin(), header.end(), ',')) << line;
  std::vector<std::string> f;
  std::stringstream fields(line);
  for (std::string x; std::getline(fields, x, ',');) f.push_back(x);
  EXPECT_EQ(f[7], "0");
  EXPECT_GE(std::stod(f[9]), 3.0) << line;  // seconds_felt: the player kept going past the song's end
}

TEST_F(StudyE2e, BadInputIsOneLineAndExit2) {
  const auto no_id = test::run_command(test::kHmp + " study --no-audio --out '" + dir_.string() + "' </dev/null");
  EXPECT_EQ(no_id.status, 2);
  EXPECT_NE(no_id.err.find("--participant"), std::string::npos) << no_id.err;
  const auto bad_dir = test::run_command(test::kHmp + " study --participant x --out /nonexistent/dir </dev/null");
  EXPECT_EQ(bad_dir.status, 2);
  std::ofstream(dir_ / "bad.csv") << "participant,experiment\n";
  const auto bad = test::run_command(test::kHmp + " study analyze '" + (dir_ / "bad.csv").string() + "'");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("bad.csv:1:"), std::string::npos) << bad.err;
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1);
  const auto missing = test::run_command(test::kHmp + " study analyze '" + (dir_ / "none.csv").string() + "'");
  EXPECT_EQ(missing.status, 2);
  // A practice song without the practice instruments, or one that cannot be read: one line, exit 2,
  // no results file and no journal.
  midi_test::Events piano;
  piano.name(0, "piano").program(0, 0, 0).on(0, 0, 60).off(480, 0, 60).end();
  const midi_test::Bytes bytes = midi_test::smf(1, 480, {piano});
  std::ofstream(dir_ / "piano.mid", std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  // A song without a note: no track has notes to list (the message's list of them was cut from an empty
  // text, an out_of_range exception and exit 1).
  midi_test::Events silent;
  silent.name(0, "violin").end();
  const midi_test::Bytes quiet = midi_test::smf(1, 480, {silent});
  std::ofstream(dir_ / "silent.mid", std::ios::binary)
      .write(reinterpret_cast<const char*>(quiet.data()), static_cast<std::streamsize>(quiet.size()));
  for (const std::string& song :
       {(dir_ / "piano.mid").string(), (dir_ / "absent.mid").string(), (dir_ / "silent.mid").string()}) {
    const auto r = test::run_command(test::kHmp + " study --participant q --no-audio --practice-song '" + song +
                                     "' --out '" + dir_.string() + "' </dev/null");
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(song), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "study-results.csv"));
    EXPECT_FALSE(fs::exists(dir_ / "study-q.journal"));
  }
}

}  // namespace
