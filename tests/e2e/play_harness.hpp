#pragma once
// Shared pieces of the end-to-end tests of `hmp play`: the demo song, running the hmp binary, an
// independent count of a passage's notes from `hmp info --json --notes`, the --log parser, and a
// library-level session (Player on any Transport, without audio) run on a thread.
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/audio/audio_player.hpp"
#include "host/midi/smf_reader.hpp"
#include "host/player/device_link.hpp"
#include "host/player/player.hpp"
#include "host/transport/transport.hpp"

namespace hmp::test {

inline const std::string kDemo = std::string(HMP_REPO_DIR) + "/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid";
inline const std::string kHmp = std::string(HMP_BIN_DIR) + "/hmp";

struct CommandResult {
  int status = -1;  // exit code, or -1 when it did not exit normally
  std::string out;  // stdout (stderr goes to err)
  std::string err;
};

// Runs a shell command line; stdout and stderr are captured separately.
inline CommandResult run_command(const std::string& command) {
  char err_path[] = "/tmp/hmp-e2e-err-XXXXXX";
  const int fd = ::mkstemp(err_path);
  ::close(fd);
  CommandResult r;
  FILE* p = ::popen((command + " 2>" + err_path).c_str(), "r");
  if (p == nullptr) return r;
  std::array<char, 4096> buf{};
  std::size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int status = ::pclose(p);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(err_path);
  std::stringstream s;
  s << in.rdbuf();
  r.err = s.str();
  std::remove(err_path);
  return r;
}

// Starts `hmp ARGS…` with stdin on a pipe that stays open (a person still at the keyboard), stdout
// discarded and stderr into `err_path` (or discarded); returns its pid and the pipe's write end.
inline std::pair<pid_t, int> start_hmp_with_keyboard(std::vector<std::string> args, const std::string& err_path = "") {
  int in[2];
  if (::pipe(in) != 0) return {-1, -1};
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(in[0], STDIN_FILENO);
    ::close(in[1]);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, STDOUT_FILENO);
    const int err = err_path.empty() ? null : ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(err, STDERR_FILENO);
    args.insert(args.begin(), "hmp");
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(kHmp.c_str(), argv.data());
    ::_exit(127);
  }
  ::close(in[0]);
  return {pid, in[1]};
}

// (key, start_s) of every note of `track` starting in [from_s, to_s), from `hmp info --json --notes`:
// the song as the MIDI reader sees it, without the player's code.
inline std::vector<std::pair<int, double>> passage_notes(std::uint32_t track, double from_s, double to_s) {
  const CommandResult info = run_command(kHmp + " info '" + kDemo + "' --json --notes");
  std::vector<std::pair<int, double>> out;
  if (info.status != 0) return out;
  const nlohmann::json j = nlohmann::json::parse(info.out);
  for (const auto& n : j.at("notes")) {
    const double start = n.at("start_s").get<double>();
    if (n.at("track").get<std::uint32_t>() == track && start >= from_s && start < to_s) {
      out.emplace_back(n.at("key").get<int>(), start);
    }
  }
  return out;
}

struct LogEntry {
  std::uint32_t track = 0;
  int key = 0;
  double start_s = 0;
  std::uint64_t scheduled = 0, actual = 0;
};

struct ParsedLog {
  std::vector<LogEntry> notes;
  std::optional<nlohmann::json> summary;
  std::vector<nlohmann::json> song_ends;      // a playlist's lines at the end of each song
  std::vector<nlohmann::json> between_songs;  // the lines before each song is read (its RSS)
  int lines_after_summary = 0;
};

inline ParsedLog parse_log(const std::string& path) {
  ParsedLog log;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const nlohmann::json j = nlohmann::json::parse(line);
    if (log.summary) ++log.lines_after_summary;
    if (j.contains("summary")) {
      log.summary = j.at("summary");
      continue;
    }
    if (j.contains("song_end")) {
      log.song_ends.push_back(j.at("song_end"));
      continue;
    }
    if (j.contains("between_songs")) {
      log.between_songs.push_back(j.at("between_songs"));
      continue;
    }
    log.notes.push_back({j.at("track").get<std::uint32_t>(), j.at("key").get<int>(), j.at("start_s").get<double>(),
                         j.at("scheduled_tick").get<std::uint64_t>(), j.at("actual_tick").get<std::uint64_t>()});
  }
  return log;
}

// A device's play log (--log) against the passage's notes from `hmp info`: as many notes, each started on
// the tick it was scheduled for, and a summary with every note played, none late or rejected.
// The timing half of expect_every_note_on_its_tick, for HMP_SKIP_IF_TOO_LOADED (tests/support/load_guard.hpp):
// the log has every note, each on its tick, and none late.
inline bool every_note_on_its_tick(const std::string& log_path, std::size_t expected_notes) {
  const ParsedLog log = parse_log(log_path);
  if (log.notes.size() != expected_notes || !log.summary || log.summary->value("late", -1) != 0) return false;
  for (const LogEntry& e : log.notes) {
    if (e.actual != e.scheduled) return false;
  }
  return true;
}

inline void expect_every_note_on_its_tick(const std::string& log_path, std::size_t expected_notes,
                                          const std::string& context) {
  const ParsedLog log = parse_log(log_path);
  ASSERT_EQ(log.notes.size(), expected_notes)
      << context << "\nsummary: " << (log.summary ? log.summary->dump() : std::string("none"));
  for (const LogEntry& e : log.notes) EXPECT_EQ(e.actual, e.scheduled) << "key " << e.key << " at " << e.start_s;
  ASSERT_TRUE(log.summary.has_value()) << context;
  EXPECT_EQ(log.summary->at("notes_played").get<std::size_t>(), expected_notes);
  EXPECT_EQ(log.summary->at("late").get<int>(), 0);
  EXPECT_EQ(log.summary->at("rejected").get<int>(), 0);
}

inline const midi::Song& demo_song() {
  static const midi::Song song = midi::load_song(kDemo).song;
  return song;
}

// A Player on a given link, silent (no audio device), run on its own thread.
class Session {
 public:
  Session(transport::Transport& link, player::PlayerOptions options) : link_(link), audio_(silent()) {
    audio_.set_events({});
    link_.connect();
    options.on_started = [this](const player::StartedNote& n) {
      std::lock_guard lock(mutex_);
      started_.push_back(n);
    };
    player_ = std::make_unique<player::Player>(link_, audio_, demo_song(), std::move(options));
  }
  ~Session() { join(); }

  void start() {
    thread_ = std::thread([this] {
      try {
        outcome_ = player_->run();
      } catch (const player::LinkError& e) {
        std::lock_guard lock(mutex_);
        error_ = e.what();
        error_at_ = std::chrono::steady_clock::now();
      }
    });
  }
  void join() {
    if (thread_.joinable()) thread_.join();
  }
  player::Player& player() { return *player_; }
  player::DeviceLink& link() { return link_; }
  audio::AudioPlayer& audio() { return audio_; }
  std::optional<player::Outcome> outcome() const { return outcome_; }
  std::string error() {
    std::lock_guard lock(mutex_);
    return error_;
  }
  std::chrono::steady_clock::time_point error_at() {
    std::lock_guard lock(mutex_);
    return error_at_;
  }
  std::vector<player::StartedNote> started() {
    std::lock_guard lock(mutex_);
    return started_;
  }

 private:
  static audio::AudioOptions silent() {
    audio::AudioOptions o;
    o.enabled = false;
    return o;
  }
  player::DeviceLink link_;
  audio::AudioPlayer audio_;
  std::unique_ptr<player::Player> player_;
  std::thread thread_;
  std::mutex mutex_;
  std::optional<player::Outcome> outcome_;
  std::string error_;
  std::chrono::steady_clock::time_point error_at_{};
  std::vector<player::StartedNote> started_;
};

inline player::PlayerOptions passage(std::uint32_t track, double from_s, double to_s) {
  player::PlayerOptions o;
  o.track = track;
  o.from_us = static_cast<std::int64_t>(from_s * 1e6);
  o.to_us = static_cast<std::int64_t>(to_s * 1e6);
  return o;
}

}  // namespace hmp::test
