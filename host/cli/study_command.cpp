// hmp study --participant ID [--age N] [--sex …] [--handedness …] [--experiment 1|2|both] [--seed N] [--song FILE]
//           [--practice-song FILE] [--out DIR] [--device …]
// hmp study analyze FILES... [--json] [--out fig.png]
// — the paper's user study (design §15). The session logic is host/study/ (no I/O); this file is the
// command line, the files and the terminal front-end: keys in, prompts out, the player driven.
#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <map>
#include <random>

#include <fmt/format.h>

#include "host/audio/audio_events.hpp"
#include "host/audio/audio_player.hpp"
#include "host/cli/commands.hpp"
#include "host/cli/device_hello.hpp"
#include "host/cli/song_options.hpp"
#include "host/cli/study_view.hpp"
#include "host/common/error.hpp"
#include "host/common/input_file.hpp"
#include "host/common/install_layout.hpp"
#include "host/common/printable.hpp"
#include "host/output/output_file.hpp"
#include "host/player/live_terminal.hpp"
#include "host/player/player.hpp"
#include "host/study/analysis.hpp"
#include "host/cli/study_figure.hpp"
#include "host/study/session.hpp"

namespace hmp::cli {

namespace {

struct StudyOptions {
  std::optional<std::string> participant;
  std::string experiment = "both";
  std::optional<std::uint64_t> seed;
  study::ParticipantTexts participant_data;  // --age, --sex, --handedness as typed ("" = not given)
  std::string song = install::example("bach-bwv1050-brandenburg5-mvt3-allegro.mid").string();
  std::string practice_song = install::example("bach-bwv1079-trio-sonata-largo.mid").string();
  std::string out = ".";
  std::string device = "sim";
  bool no_view = false;  // the terminal only
  bool window = false;   // the window or nothing (exit 2)
  AudioCliOptions audio;
};

struct AnalyzeOptions {
  std::vector<std::string> files;
  bool json = false;
  std::optional<std::string> figure;
  bool force = false;
};

double unix_now() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

// A session's own file: none yet is nullopt; anything else there (a directory, say) is refused as every
// file the user names is (host/common/input_file.hpp).
std::optional<std::string> read_text(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0 && errno == ENOENT) return std::nullopt;
  return read_input_file(path);
}

// Appends in one write and syncs, so that a crash leaves whole rounds (a round's rows go together).
void append_text(const std::string& path, const std::string& text) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw BadInput(fmt::format("{}: cannot open for appending", path));
  const ssize_t n = ::write(fd, text.data(), text.size());
  const bool synced = ::fsync(fd) == 0;
  ::close(fd);
  if (n != static_cast<ssize_t>(text.size()) || !synced)
    throw std::runtime_error(fmt::format("{}: write failed", path));
}

// The session journal: the seed and experiments, written before the first round so that a session
// interrupted before any row was written resumes with the same plan.
struct Journal {
  std::uint64_t seed = 0;
  std::string experiments;
};

std::optional<Journal> read_journal(const std::string& path) {
  const auto text = read_text(path);
  if (!text) return std::nullopt;
  Journal j;
  unsigned long long seed = 0;
  char experiments[16] = {};
  if (std::sscanf(text->c_str(), "seed=%llu\nexperiments=%15s", &seed, experiments) != 2) {
    throw BadInput(fmt::format("{}:1: not a study journal (expected seed=N and experiments=…)", path));
  }
  j.seed = seed;
  j.experiments = experiments;
  return j;
}

// The demo's track of an instrument: the first track with notes whose name starts with it (the demo
// has "violin" twice and "harpsichordUp:"/"harpsichordDown:"), else --track's rules.
std::uint32_t instrument_track(const midi::Song& song, const std::string& instrument) {
  for (const midi::Track& t : song.tracks) {
    if (t.note_count == 0 || t.name.size() < instrument.size()) continue;
    bool same = true;
    for (std::size_t i = 0; i < instrument.size(); ++i) {
      same = same && std::tolower(static_cast<unsigned char>(t.name[i])) == instrument[i];
    }
    if (same) return t.index;
  }
  return select_track(song, instrument);
}

// A song of the study, where it came from and the tracks of its instruments; a song that cannot be read,
// or lacks one of them, is refused naming the option that gave it.
struct StudySong {
  std::string path;
  midi::Song song;
  std::map<std::string, std::uint32_t> tracks;
};
template <std::size_t N>
StudySong load_study_song(const std::string& option, const std::string& path,
                          const std::array<const char*, N>& instruments) {
  StudySong s{path, {}, {}};
  try {
    s.song = midi::load_song(path).song;
  } catch (const BadInput& e) {
    throw BadInput(fmt::format("{} {}", option, e.what()));
  }
  for (const char* i : instruments) {
    try {
      s.tracks[i] = instrument_track(s.song, i);
    } catch (const BadInput& e) {
      throw BadInput(fmt::format("{} {}: no {} track ({})", option, printable(path), i, e.what()));
    }
  }
  return s;
}

// The player's name of a study envelope, and its place in the player's `e` cycle (auto → square →
// triangle): the study switches by posting that many cycle commands, the same path as the `e` key.
const char* player_envelope(study::Envelope e) {
  return e == study::Envelope::analogue ? "auto" : study::envelope_name(e);
}
int cycle_index(study::Envelope e) { return e == study::Envelope::analogue ? 0 : e == study::Envelope::square ? 1 : 2; }

// Keys from the terminal (raw mode), or from a pipe: scripted participants type through the same path,
// and through the same decoding (an arrow key's escape sequence is not the letters in it).
class KeySource {
 public:
  std::optional<char> next() {
    if (raw_.active()) return raw_.next_char();
    while (!ended_) {
      pollfd p{STDIN_FILENO, POLLIN, 0};
      if (::poll(&p, 1, 0) <= 0) return decoder_.idle();
      unsigned char c = 0;
      if (::read(STDIN_FILENO, &c, 1) != 1) {
        ended_ = true;  // end of input (or an error): nobody is there to answer
        return decoder_.idle();
      }
      if (const std::optional<char> key = decoder_.feed(c)) return key;
    }
    return std::nullopt;
  }
  bool ended() const { return ended_; }
  void restore() { raw_.restore(); }

 private:
  player::RawKeys raw_;
  player::KeyDecoder decoder_;  // the pipe's
  bool ended_ = false;
};

std::vector<int> experiments_of(const std::string& text) {
  if (text == "1") return {1};
  if (text == "2") return {2};
  if (text == "both") return {1, 2};
  throw BadInput(fmt::format("--experiment {}: 1, 2 or both", text));
}

// The options of the participant's data, in study::ParticipantTexts order (the messages name them).
const study::ParticipantTexts kParticipantOptions{"--age", "--sex", "--handedness"};

// A results file from before the participant's columns gets rows in its own layout, which has no room
// for the participant's data: refused rather than dropped.
void check_room_for(const study::ParticipantData& given, study::Columns columns, const std::string& results_path) {
  if (columns == study::Columns::with_participant || given == study::ParticipantData{}) return;
  throw BadInput(
      fmt::format("{}: written before the age, sex and handedness columns; record {}, {} and {} in a new --out "
                  "directory",
                  printable(results_path), kParticipantOptions[0], kParticipantOptions[1], kParticipantOptions[2]));
}

// The round in a few words, for the window's top line (the prompt follows it there).
std::string window_label(const study::Round& r, std::size_t index, std::size_t total) {
  if (r.practice) return fmt::format("Practice {} of 2: {} alone", r.position, r.instrument);
  return fmt::format("Round {} of {}: {}, experiment {}", index + 1, total, r.instrument, r.experiment);
}

std::string round_title(const study::Round& r, std::size_t index, std::size_t total) {
  if (r.practice) {
    return fmt::format("Practice {} of 2: {} alone (mapping {}). Feel keys 0, 1, 2; rank them A (best), B, C; Enter.",
                       r.position, r.instrument, study::mapping_of_experiment(r.experiment));
  }
  return fmt::format("Round {} of {} — experiment {} ({} mapping), instrument {} of 4: {}", index + 1, total,
                     r.experiment, study::mapping_of_experiment(r.experiment), r.position, r.instrument);
}

int run_study(const StudyOptions& o) {
  if (!o.participant || !study::valid_participant_id(*o.participant)) {
    throw BadInput(
        fmt::format("--participant {}: 1–64 letters, digits, '_', '-' or '.' (required)", o.participant.value_or("")));
  }
  const std::string& participant = *o.participant;
  std::vector<int> experiments = experiments_of(o.experiment);
  if (o.window && o.no_view) throw BadInput("--window and --no-view: one or the other");
  const study::ParticipantData given = study::parse_participant(o.participant_data, kParticipantOptions, "");
  const audio::AudioOptions audio_opts = audio_options(o.audio);  // checks --soundfont, before any work
  // The songs before any file is written: the main rounds' instruments from --song, the practice
  // rounds' from --practice-song (another piece, as in the paper).
  const StudySong main_song = load_study_song("--song", o.song, study::kInstruments);
  const StudySong practice_song = load_study_song("--practice-song", o.practice_song, study::kPracticeInstruments);
  struct stat st {};
  if (::stat(o.out.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
    throw BadInput(fmt::format("--out {}: not a directory", o.out));
  const std::string results_path = o.out + "/study-results.csv";
  const std::string journal_path = o.out + "/study-" + participant + ".journal";

  // The results file first: a bad one, or this participant recorded with another seed, age, sex or
  // handedness, is refused before anything is written.
  std::vector<study::ResultRow> existing;
  const auto results_text = read_text(results_path);
  if (results_text) existing = study::parse_results(*results_text, results_path);
  const study::Columns columns =
      results_text ? study::results_columns(*results_text) : study::Columns::with_participant;
  check_room_for(given, columns, results_path);

  std::uint64_t seed = 0;
  const auto journal = read_journal(journal_path);
  if (journal) {
    if (o.seed && *o.seed != journal->seed) {
      throw BadInput(fmt::format("{}: participant {} began with seed {}, not {} (another id starts afresh)",
                                 journal_path, participant, journal->seed, *o.seed));
    }
    if (journal->experiments != o.experiment) {
      throw BadInput(fmt::format("{}: participant {} began with --experiment {}", journal_path, participant,
                                 journal->experiments));
    }
    seed = journal->seed;
  } else {
    seed = o.seed ? *o.seed : (std::uint64_t{std::random_device{}()} << 32 | std::random_device{}());
  }
  study::Session session({participant, seed, experiments, version_string(), given}, existing);
  // Said once the session is accepted: a refused one gets its error as the only line.
  if (journal) {
    std::fprintf(stderr, "resuming participant %s (seed %llu)\n", participant.c_str(),
                 static_cast<unsigned long long>(seed));
  }
  if (session.done()) {
    std::printf("participant %s: all %zu rounds are done (%s)\n", participant.c_str(), session.plan().size(),
                results_path.c_str());
    return kExitOk;
  }

  audio::AudioPlayer audio(audio_opts);
  // The animation window on the first round's song (2015 §6.1: the complete environment); without one,
  // the terminal alone, with one warning — or, with --window, one line and exit 2, nothing written.
  std::unique_ptr<StudyWindow> window;
  bool want_window = !o.no_view;
  auto open_window = [&](const StudySong& s) {
    window.reset();
    std::string why;
    window = StudyWindow::open(s.song, audio, fmt::format("hmp study — participant {} — {}", participant, s.path), why);
    if (window) return;
    if (o.window) throw BadInput(fmt::format("--window: no animation window: {}", why));
    std::fprintf(stderr,
                 "warning: no animation window: %s; the study goes on in the terminal (--no-view: do not try)\n",
                 why.c_str());
    want_window = false;
  };
  const auto song_of = [&](const study::Round& r) -> const StudySong& {
    return r.practice ? practice_song : main_song;
  };
  if (want_window) open_window(song_of(session.plan()[session.rounds_done()]));

  haptics::HapticOptions haptic;
  transport::OpenedDevice opened = transport::open_device(transport::parse_device_spec(o.device), haptic.tick_hz);
  if (!opened.note.empty()) std::fprintf(stderr, "%s\n", opened.note.c_str());
  player::DeviceLink link(*opened.transport, link_options_for(opened));
  connect_and_describe(link, opened);

  if (!journal) append_text(journal_path, fmt::format("seed={}\nexperiments={}\n", seed, o.experiment));
  if (!results_text || results_text->empty()) append_text(results_path, std::string(study::kResultsHeader) + "\n");

  KeySource keys;
  const bool scripted = !isatty(STDIN_FILENO);
  player::install_stop_signals();
  std::printf("participant %s, seed %llu: %zu of %zu rounds done; results go to %s\n", participant.c_str(),
              static_cast<unsigned long long>(seed), session.rounds_done(), session.plan().size(),
              results_path.c_str());
  std::fflush(stdout);

  std::size_t round_index = session.rounds_done();
  std::string said_last;  // what the round before ended with (a practice round: the analogue key)
  while (!session.done()) {
    study::RoundState& round = session.begin_round(unix_now());
    const study::Round plan = round.round();
    const StudySong& played = song_of(plan);
    const midi::Song& song = played.song;
    const std::uint32_t track = played.tracks.at(plan.instrument);
    if (scripted) {
      std::fprintf(stderr, "study: round %s %d %s (track %u of %s); key 0\n", plan.practice ? "practice" : "main",
                   plan.experiment, plan.instrument.c_str(), track, played.path.c_str());
    }
    std::printf("\n%s\n%s\n", round_title(plan, round_index, session.plan().size()).c_str(), round.prompt().c_str());
    std::fflush(stdout);
    if (want_window && (!window || &window->song() != &song)) open_window(played);
    const std::string label = window_label(plan, round_index, session.plan().size());
    if (window) window->show(track, label + "     " + round.prompt() + (said_last.empty() ? "" : "     " + said_last));
    said_last.clear();
    // Practice rounds: the instrument alone; the others' sound is left out.
    audio.set_events(plan.practice ? audio::audio_events(song.track_notes(track), song.tempo_map)
                                   : audio::audio_events(song));

    bool round_over = false, interrupted = false;
    while (!round_over && !interrupted) {  // the song loops until the round is ranked
      player::PlayerOptions po;
      po.track = track;
      po.haptic = haptic;
      po.haptic.mapping = plan.experiment == 2 ? mapping::Mode::constant : mapping::Mode::paper;
      po.haptic.key_scope = haptics::KeyScope::song;  // the paper's k_min, k_max, k_ε "in the song" (§5.4)
      const study::Envelope playing = session.current()->selected_envelope();
      po.haptic.envelope = player_envelope(playing);
      // The player's notices name the envelope, which the participant must not see; a script (stdin not a
      // terminal) gets them on stderr, each after the study's own "study: key K" line, to check the switch.
      po.on_message = [&](const std::string& text) {
        if (scripted) std::fprintf(stderr, "player: %s\n", text.c_str());
      };
      player::Player* running = nullptr;
      study::Envelope in_player = playing;
      po.on_idle = [&] {
        if (player::stop_signal() != 0) {
          interrupted = true;
          running->post(player::Command::interrupt);
          return;
        }
        while (!round_over) {
          auto c = keys.next();
          if (!c && window) c = window->next_key();
          if (c == 'q') {  // q or Esc, in the terminal or the window, or the window closed: as Ctrl-C
            interrupted = true;
            running->post(player::Command::interrupt);
            return;
          }
          if (!c) break;
          const auto action = study::action_for_key(*c);
          if (!action) continue;
          const study::Reply reply = session.act(*action, unix_now());
          if (reply.finished) {
            std::string rows;
            for (const study::ResultRow& r : session.take_rows()) rows += study::format_row(r, columns) + "\n";
            append_text(results_path, rows);
            std::printf("%s\n", reply.message.c_str());
            said_last = reply.message;  // the window shows it with the next round, as the terminal did
            round_over = true;
            running->post(player::Command::quit);
            break;
          }
          std::printf("%s\n%s\n", reply.message.c_str(), session.current()->prompt().c_str());
          if (window) window->show(track, label + "     " + session.current()->prompt() + "     " + reply.message);
          if (reply.envelope_changed) {
            const study::Envelope next = session.current()->selected_envelope();
            if (scripted) std::fprintf(stderr, "study: key %d\n", session.current()->selected_key());
            for (int n = (cycle_index(next) - cycle_index(in_player) + 3) % 3; n > 0; --n)
              running->post(player::Command::cycle_envelope);
            in_player = next;
            break;  // the player switches before the next key is read
          }
        }
        std::fflush(stdout);
        if (!round_over && keys.ended()) {
          interrupted = true;  // input ended mid-round: stop as after Ctrl-C, resumable
          running->post(player::Command::interrupt);
        }
      };
      player::Player player(link, audio, song, po);
      running = &player;
      player.run();
    }
    if (interrupted) {
      keys.restore();
      std::fprintf(stderr,
                   "study interrupted in round %zu of %zu; the finished rounds are in %s. Run the same command "
                   "again to resume.\n",
                   round_index + 1, session.plan().size(), results_path.c_str());
      return 128 + (player::stop_signal() != 0 ? player::stop_signal() : 2);
    }
    ++round_index;
  }
  keys.restore();
  std::printf("\nthank you: participant %s has finished all %zu rounds (%s)\n", participant.c_str(),
              session.plan().size(), results_path.c_str());
  return kExitOk;
}

int run_analyze(const AnalyzeOptions& o) {
  // The figure's file first: a name that cannot be written fails before the table is printed.
  if (o.figure && *o.figure == "-") throw BadInput("--out -: the figure needs a file name");
  if (o.figure) output::check_writable(*o.figure, o.force);
  std::vector<study::ResultRow> rows;
  for (const std::string& file : o.files) {
    const std::string text = read_input_file(file);
    if (text.empty()) throw BadInput(fmt::format("{}:1: empty file (no header)", printable(file)));
    for (study::ResultRow& r : study::parse_results(text, file)) rows.push_back(std::move(r));
  }
  const std::vector<study::GroupAnalysis> groups = study::analyze(rows);
  if (groups.empty()) throw BadInput("no main-round rows to analyse (practice rows are not analysed)");
  const study::ParticipantSummary participants = study::summarize(study::analysed_participants(rows));
  if (o.json) {
    std::printf("%s\n", study::to_json(groups).dump(2).c_str());
  } else {
    std::printf("%s\n%s", study::format_summary(participants).c_str(), study::format_report(groups).c_str());
  }
  if (o.figure) {
    write_study_figure(groups, *o.figure, true);  // checked above (absent, --force, or a "yes")
    std::fprintf(stderr, "figure: %s\n", o.figure->c_str());
  }
  return kExitOk;
}

}  // namespace

void register_study(CLI::App& app, Registry& registry) {
  auto o = std::make_shared<StudyOptions>();
  CLI::App* cmd = app.add_subcommand(
      "study",
      "Run the paper's user study for one participant (keys 0/1/2 switch, a/b/c rank, u undo, Enter next); "
      "`study analyze` evaluates results");
  cmd->add_option("--participant", o->participant,
                  "Participant id (letters, digits, _ - .); required to run a session");
  cmd->add_option("--experiment", o->experiment, "1 (mapping paper), 2 (mapping constant) or both")
      ->check(CLI::IsMember({"1", "2", "both"}))
      ->capture_default_str();
  const std::array<const char*, study::kParticipantFields> what{"The participant's age", "The participant's sex",
                                                                "The participant's handedness"};
  for (std::size_t i = 0; i < study::kParticipantFields; ++i) {
    cmd->add_option(
        kParticipantOptions[i], o->participant_data[i],
        fmt::format("{}: {} (optional; kept in every row of the results)", what[i], study::participant_allowed(i)));
  }
  cmd->add_option("--seed", o->seed, "Seed of the random orders (default: random; stored with the results)")
      ->check(CLI::Validator(
          [](std::string& text) {
            // Digits alone: CLI11 takes "-1" for an unsigned number as its wrap-around, 2^64 − 1. An empty
            // value is left to the check every option has (commands.cpp).
            std::uint64_t value = 0;
            const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
            const bool digits = text.find_first_not_of("0123456789") == std::string::npos;
            return text.empty() || (digits && ec == std::errc{} && end == text.data() + text.size())
                       ? std::string()
                       : text + " is not a whole number from 0 to 18446744073709551615";
          },
          ""));
  cmd->add_option("--song", o->song, "The song of the main rounds (default: the demo)")->capture_default_str();
  cmd->add_option("--practice-song", o->practice_song,
                  "The song of the practice rounds, with a violin and a contrabass track (default: BWV 1079's Largo)")
      ->capture_default_str();
  cmd->add_option("--out", o->out, "Directory of study-results.csv and the session journals")->capture_default_str();
  cmd->add_flag("--no-view", o->no_view, "No animation window: the terminal only");
  cmd->add_flag("--window", o->window,
                "The animation window or nothing: without a display, exit 2 before anything is written");
  cmd->add_option("--device", o->device, "sim (default), qemu, auto, hid[:VID:PID], serial:PATH")
      ->capture_default_str();
  add_audio_options(cmd, o->audio);

  auto a = std::make_shared<AnalyzeOptions>();
  CLI::App* analyze = cmd->add_subcommand(
      "analyze",
      "Per experiment and instrument: first-place votes, pairwise majorities, Copeland winners, Friedman, Kendall's W");
  analyze->add_option("FILES", a->files, "Results files (study-results.csv)")->required();
  analyze->add_flag("--json", a->json, "JSON instead of the table");
  analyze->add_option("--out", a->figure, "PNG like the paper's Figure 3");
  analyze->add_flag("-f,--force", a->force, "Overwrite an existing --out file");
  analyze->callback([a, &registry] { registry.set([a] { return run_analyze(*a); }); });
  cmd->callback([o, analyze, &registry] {
    if (analyze->parsed()) return;
    registry.set([o] { return run_study(*o); });
  });
}

}  // namespace hmp::cli
