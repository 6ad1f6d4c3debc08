// hmp play SONG... [--track T] [--device …] [--no-audio] [--no-view] [--from S] [--to S] [--log FILE] [--loop]
// [--shuffle] — the main job (design §3): the song's audio with one track felt on the device, song after
// song. The player itself is host/player/; this file is the command line, the terminal and the messages.
#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>

#include <fmt/format.h>

#include "host/audio/audio_events.hpp"
#include "host/audio/audio_player.hpp"
#include "host/live/midi_out.hpp"
#include "host/live/midi_port.hpp"
#include "host/audio/virtual_card.hpp"
#include "host/cli/commands.hpp"
#include "host/cli/device_hello.hpp"
#include "host/cli/play_view.hpp"
#include "host/cli/song_options.hpp"
#include "host/common/error.hpp"
#include "host/common/process_memory.hpp"
#include "host/common/song_window.hpp"
#include "host/config/config.hpp"
#include "host/midi/gm.hpp"
#include "host/player/device_link.hpp"
#include "host/player/live_terminal.hpp"
#include "host/player/play_log.hpp"
#include "host/player/player.hpp"
#include "host/player/playlist.hpp"
#include "host/transport/handshake.hpp"

namespace hmp::cli {

namespace {

struct PlayOptions {
  std::vector<std::string> songs;
  std::optional<std::string> track;
  std::string device = "auto";
  AudioCliOptions audio;
  bool no_view = false;
  bool fullscreen = false;
  double speed = 1.0;
  std::optional<double> from_s, to_s;
  std::optional<std::string> log;
  bool force = false;
  bool loop = false, shuffle = false;
  bool exit_on_device_loss = false;
  std::optional<std::string> midi_out;
  HapticCliOptions haptic;
};

// --midi-out's port, opened (JACK where a server runs, else the ALSA sequencer); bad input when it is not
// there.
std::unique_ptr<live::MidiOutput> open_midi_out(const std::string& port) {
  std::string why;
  const live::MidiPortBackend* b = live::midi_port_backend(&why);
  if (b == nullptr) throw BadInput("--midi-out: no MIDI ports: " + why);
  const live::MidiApi api = live::default_api(*b);
  std::unique_ptr<live::MidiOutput> out = b->open_output(api, port == "-" ? "" : port, why);
  if (!out) throw BadInput(fmt::format("--midi-out {}: {}", port, why));
  return out;
}

// A song read and its haptic track chosen, ready to play.
struct ReadySong {
  midi::Song song;
  std::uint32_t track = 0;
};

// Reads `path` and chooses its track: --track when the song has it, else the first with a Table 1
// instrument. One song alone refuses a --track it does not have; in a playlist, each song that lacks it
// plays its default track, said once per song. Throws BadInput naming the file.
ReadySong ready_song(const PlayOptions& o, const std::string& path, bool alone) {
  ReadySong out;
  midi::ReadResult r = midi::load_song(path);
  std::optional<std::uint32_t> chosen;
  std::string unplayable_track;  // in a playlist: why --track is not this song's
  haptics::check_song_then_warn(r, warn_on_stderr, [&] {
    // Nothing to feel or hear, whichever --track: refused alone, skipped in a playlist.
    if (std::none_of(r.song.tracks.begin(), r.song.tracks.end(), [](const midi::Track& t) { return t.note_count > 0; }))
      throw BadInput("the song has no notes to play");
    check_start_in_song(o.from_s, r.song.duration_us);
    if (!o.track) return;
    try {
      chosen = select_track(r.song, *o.track);
    } catch (const BadInput& e) {
      if (alone) throw;
      unplayable_track = e.what();
    }
  });
  if (!unplayable_track.empty())
    std::fprintf(stderr, "%s: %s: the default track instead\n", path.c_str(), unplayable_track.c_str());
  out.song = std::move(r.song);
  out.track = chosen ? *chosen : default_haptic_track(out.song);
  if (!chosen) {
    const char* why = has_table1_instrument(out.song.tracks[out.track])
                          ? "the first whose instrument has a Table 1 envelope"
                          : "no instrument has a Table 1 envelope: the first with notes";
    std::fprintf(stderr, "haptic track %s (%s; choose with --track or the t key)\n",
                 describe_track(out.song, out.track).c_str(), why);
  }
  return out;
}

void print_summary(const player::Counters& c, const player::Snapshot& s, std::size_t window_notes,
                   const std::string& device) {
  std::printf(
      "%s\n",
      fmt::format("{}played {} of {} notes sent ({} in the window) of track {} \"{}\" on {}: late {}, stolen {}, "
                  "rejected {}{}{}{}; stopped at {}",
                  s.song_label.empty() ? "" : s.song_label + ": ", c.notes_played, c.notes_sent, window_notes, s.track,
                  s.track_name, device, c.late, c.stolen, c.rejected,
                  c.skipped ? fmt::format(", skipped {}", c.skipped) : "",
                  c.cancelled ? fmt::format(", cancelled {} (ahead of the stop)", c.cancelled) : "",
                  c.recoveries ? fmt::format(", recovered {} time(s)", c.recoveries) : "", format_time(s.song_us))
          .c_str());
  std::fflush(stdout);
}

player::Counters& operator+=(player::Counters& a, const player::Counters& b) {
  a.notes_sent += b.notes_sent;
  a.notes_played += b.notes_played;
  a.late += b.late;
  a.stolen += b.stolen;
  a.rejected += b.rejected;
  a.skipped += b.skipped;
  a.cancelled += b.cancelled;
  a.recoveries += b.recoveries;
  return a;
}

// "[2/5] name.mid" in a playlist (the pass too when looping), "" for one song.
std::string song_label(const player::Playlist& list, bool alone) {
  if (alone) return "";
  const std::string name = std::filesystem::path(list.current()).filename().string();
  return list.pass() > 0 ? fmt::format("[{}/{} pass {}] {}", list.position() + 1, list.size(), list.pass() + 1, name)
                         : fmt::format("[{}/{}] {}", list.position() + 1, list.size(), name);
}

// One song after another on the one device session, sound card, terminal and log of the run.
struct PlaylistRun {
  const PlayOptions& o;
  const player::Playlist& list;
  bool alone;
  player::DeviceLink& link;
  const protocol::HelloReply& hello;
  transport::OpenedDevice& opened;
  audio::AudioPlayer& audio;
  player::RawKeys& keys;
  player::StatusLine& status;
  player::PlayLog& log;
  player::PlayerOptions& po;
  live::MidiOutput* midi_out = nullptr;  // --midi-out
  player::Counters total{};
  player::PlayLog::Totals totals{};
  std::set<std::size_t> skipped_files;  // list indices: a file skipped on every pass counts once

  // The current song read, or nullopt after one line saying why it is skipped.
  std::optional<ReadySong> read_current() {
    try {
      return ready_song(o, list.current(), alone);
    } catch (const BadInput& e) {
      std::fprintf(stderr, "skipped %s: %s\n", list.current().c_str(), e.what());
      skipped_files.insert(list.current_index());
      return std::nullopt;
    }
  }

  // Plays `ready` to its end, a quit or a change of song, with its window where one can be had; its
  // song_end line and summary. A device lost for good (or another protocol) ends the run: LinkError, the
  // log closed whole first.
  player::Outcome play(const ReadySong& ready) {
    const midi::Song& song = ready.song;
    audio.set_events(audio::audio_events(song));
    po.track = ready.track;
    po.song_label = song_label(list, alone);
    log.begin_song(list.current_index());
    po.on_started = [this](const player::StartedNote& n) { log.started(n); };
    player::Player* running = nullptr;
    po.on_idle = [&] {
      if (player::stop_signal() != 0) running->post(player::Command::interrupt);
      while (auto key = keys.poll()) running->post(player::command_for(*key));
      status.show(running->snapshot());
      log.flush();
    };
    player::Player player(link, audio, song, po);
    running = &player;
    // The song to another synthesizer, on the clock the device's notes follow.
    std::unique_ptr<live::MidiOutSender> midi;
    if (midi_out != nullptr) {
      midi = std::make_unique<live::MidiOutSender>(
          *midi_out, audio::audio_events(song),
          live::MidiOutSender::Clock{[this] { return audio.song_time_us(); }, [this] { return audio.playing(); }});
    }
    // The animation (design §14): where there is no window to be had, one warning and the song plays on.
    std::unique_ptr<view::LiveView> window;
    if (!o.no_view) {
      haptics::HapticOptions strip = po.haptic;
      strip.tick_hz = hello.tick_hz;  // the strip shows what the device plays, at its rate
      std::string why;
      const std::string title = po.song_label.empty() ? list.current() : po.song_label;
      window = open_play_view(song, player, audio, strip,
                              {fmt::format("hmp — {}", title), opened.transport->name(), o.fullscreen}, why);
      if (!window)
        std::fprintf(stderr, "warning: no animation window: %s; the song plays on without it (--no-view: do not try)\n",
                     why.c_str());
    }
    player::Outcome outcome;
    try {
      outcome = player.run();
    } catch (const player::LinkError&) {
      status.close();
      keys.restore();
      total += player.counters();
      log.summary(total, totals);
      log.close();  // the log of a lost link is whole (summary included): kept, not removed as a cut write
      throw;
    }
    window.reset();
    if (midi) {
      const std::string why = midi->error();
      midi.reset();
      if (!why.empty()) std::fprintf(stderr, "warning: --midi-out %s: %s\n", midi_out->name().c_str(), why.c_str());
    }
    status.show(player.snapshot(), true);
    status.close();
    const player::Snapshot end = player.snapshot();
    const player::Counters counters = player.counters();
    const double song_s = static_cast<double>(std::max<std::int64_t>(0, end.song_us - end.begin_us)) / 1e6;
    log.song_end(list.current_index(), list.current(), song_s, counters);
    print_summary(counters, end, player.window_notes(), opened.transport->name());
    total += counters;
    totals.played_s += song_s;
    ++totals.songs_played;
    return outcome;
  }
};

int run_play(const PlayOptions& o) {
  haptics::HapticOptions haptic = resolve(o.haptic);
  haptic.speed = o.speed;
  haptics::validate(haptic);
  check_window_times(o.from_s, o.to_s);  // each song's end is checked as it comes
  // Refuse an existing log before any work (design §3: never overwrite without --force).
  player::PlayLog log;
  if (o.log) output::check_writable(*o.log, o.force);
  const audio::AudioOptions audio_opts = audio_options(o.audio);  // checks --soundfont, before any work

  std::vector<std::string> notes;
  std::vector<std::string> songs = player::expand_songs(o.songs, notes);
  if (songs.empty()) throw BadInput("no song to play: " + fmt::format("{}", fmt::join(notes, "; ")));
  for (const std::string& n : notes) warn_on_stderr(n);
  // One song alone keeps the single-song rules: a song that cannot be read is an error before the device.
  const bool alone = songs.size() == 1 && !o.loop;
  player::Playlist list(std::move(songs), o.loop, o.shuffle, std::random_device{}());
  std::optional<ReadySong> first;
  if (alone) first = ready_song(o, list.current(), true);

  std::unique_ptr<live::MidiOutput> midi_out;
  if (o.midi_out) midi_out = open_midi_out(*o.midi_out);  // a port that is not there: before the device
  transport::OpenedDevice opened = transport::open_device(transport::parse_device_spec(o.device), haptic.tick_hz);
  if (!opened.note.empty()) std::fprintf(stderr, "%s\n", opened.note.c_str());
  player::DeviceLink link(*opened.transport, link_options_for(opened));
  const protocol::HelloReply hello = connect_and_describe(link, opened);
  if (o.haptic.tick_hz && *o.haptic.tick_hz != hello.tick_hz) {
    std::fprintf(stderr, "warning: the device ticks at %u Hz, not %u: notes are placed at %u Hz\n", hello.tick_hz,
                 *o.haptic.tick_hz, hello.tick_hz);
  }

  audio::AudioPlayer audio(audio_opts);
  if (audio.audible()) {
    await_audio_period(audio);
    std::fprintf(stderr, "audio: %s, output latency %.1f ms (compensated)\n", audio.driver_name().c_str(),
                 audio.output_latency_s() * 1e3);
  }
  if (o.log) log = player::PlayLog(*o.log, true);  // checked above; it did not exist or --force was given

  const bool tty = isatty(STDERR_FILENO) && isatty(STDOUT_FILENO);
  player::RawKeys keys;
  player::StatusLine status(tty);
  player::install_stop_signals();
  if (keys.active()) {
    status.message(
        fmt::format("keys: space pause/resume, ←/→ seek 5 s, t/T track, e envelope, m mapping, [/] speed, {}q quit",
                    alone ? "" : "n/p song, "));
  }

  player::PlayerOptions po;
  po.haptic = haptic;
  for (const std::string& path : o.haptic.config_paths) {
    // The config's [device] table: force of full scale and vibration direction (design §11).
    const config::Config cfg = config::load(path);
    if (cfg.peak_force_n) po.settings.peak_force_n = static_cast<float>(*cfg.peak_force_n);
    if (cfg.direction) {
      for (int i = 0; i < 3; ++i)
        po.settings.direction[i] = static_cast<float>((*cfg.direction)[static_cast<std::size_t>(i)]);
    }
  }
  po.from_us = o.from_s ? saturated_us(*o.from_s) : 0;
  if (o.to_s) po.to_us = saturated_us(*o.to_s);
  po.on_message = [&](const std::string& text) { status.message(text); };
  if (!o.exit_on_device_loss) po.find_device = [&] { return transport::reopen_device(opened); };

  PlaylistRun run{o, list, alone, link, hello, opened, audio, keys, status, log, po, midi_out.get(), {}, {}, {}};
  player::Outcome outcome = player::Outcome::finished;
  int last_move = 1;  // a song that cannot be read is passed over in the direction the user went
  std::size_t played_this_pass = 0;
  for (bool more = true; more;) {
    // The last song's notes, events and player are gone: hand the heap they took back to the system, so
    // that a long playlist's memory follows the song playing, not the biggest one so far.
    malloc_trim(0);
    log.between_songs(resident_set_kib());
    std::optional<ReadySong> ready = std::move(first);
    first.reset();
    if (!ready) ready = run.read_current();
    if (ready) {
      outcome = run.play(*ready);
      ++played_this_pass;
    } else if (outcome == player::Outcome::previous_song) {
      last_move = -1;
    }
    switch (outcome) {
      case player::Outcome::quit:
      case player::Outcome::interrupted: more = false; break;
      case player::Outcome::previous_song:
        list.previous();
        last_move = -1;
        outcome = player::Outcome::finished;  // where the user went is in last_move now
        break;
      default: {
        if (outcome == player::Outcome::next_song) last_move = 1;
        if (!ready && last_move < 0 && list.position() > 0) {
          list.previous();
          break;
        }
        const std::size_t pass = list.pass();
        more = list.next();
        last_move = 1;
        if (more && list.pass() != pass) {
          // A whole pass that played nothing would loop for ever.
          if (played_this_pass == 0) {
            std::fprintf(stderr, "error: no song of the playlist could be played\n");
            more = false;
          }
          played_this_pass = 0;
        }
      }
    }
  }
  keys.restore();
  player::PlayLog::Totals totals = run.totals;
  totals.files_skipped = run.skipped_files.size();
  if (const audio::VirtualCard* card = audio.virtual_card()) {
    totals.audio_underruns = card->underruns();
    totals.audio_realtime = card->realtime();
    totals.audio_underrun_list = card->underrun_list();
  }
  log.summary(run.total, totals);
  log.close();
  if (!alone) {
    const player::Counters& t = run.total;
    std::printf("%s\n",
                fmt::format("playlist: {} song(s) played, {} file(s) skipped; notes played {} of {} sent, late {}, "
                            "stolen {}, rejected {}",
                            totals.songs_played, totals.files_skipped, t.notes_played, t.notes_sent, t.late, t.stolen,
                            t.rejected)
                    .c_str());
  }
  if (outcome == player::Outcome::interrupted) return 128 + player::stop_signal();  // as shells report a signal
  if (!run.skipped_files.empty()) return kExitBadInput;
  return kExitOk;
}

}  // namespace

void register_play(CLI::App& app, Registry& registry) {
  auto o = std::make_shared<PlayOptions>();
  CLI::App* cmd = app.add_subcommand("play", "Play a song with one track felt on the haptic device (the main job)");
  cmd->add_option("SONG", o->songs, "MIDI files or folders (their .mid/.midi files, sorted), played in order")
      ->required();
  cmd->add_option("--track", o->track,
                  "Haptic track: index, or part of its name or instrument (default: the first whose instrument has a "
                  "Table 1 envelope, else the first with notes)");
  cmd->add_option("--device", o->device, kDeviceHelp)->capture_default_str();
  add_audio_options(cmd, o->audio);
  CLI::Option* no_view = cmd->add_flag("--no-view", o->no_view, "No animation window");
  cmd->add_option("--midi-out", o->midi_out,
                  "Also send the song as MIDI, on the device's clock, to the output port whose name contains PORT "
                  "(`hmp live` with its list option shows them; - for a port of our own, hmp, to connect to)");
  cmd->add_flag("--fullscreen", o->fullscreen, "The animation window fills the screen (f toggles)")->excludes(no_view);
  cmd->add_option("--speed", o->speed,
                  "Playback speed 0.5–2 (sound and device follow; [ and ] change it while playing)")
      ->capture_default_str();
  cmd->add_option("--from", o->from_s, "Start of the passage in seconds of the song");
  cmd->add_option("--to", o->to_s, "End of the passage in seconds of the song");
  cmd->add_option("--log", o->log, "JSON lines: every note the device started, then a summary");
  cmd->add_flag("-f,--force", o->force, "Overwrite an existing log file");
  cmd->add_flag("--loop", o->loop, "Play the songs again from the first after the last, until q");
  cmd->add_flag("--shuffle", o->shuffle, "Play the songs in a random order (a new one on every pass)");
  cmd->add_flag("--exit-on-device-loss", o->exit_on_device_loss,
                "A device that is lost ends the run with exit 1 (default: wait for it to come back)");
  add_haptic_options(cmd, o->haptic);
  cmd->callback([o, &registry] { registry.set([o] { return run_play(*o); }); });
}

}  // namespace hmp::cli
