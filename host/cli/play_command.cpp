// hmp play SONG [--track T] [--device …] [--no-audio] [--no-view] [--from S] [--to S] [--log FILE]
// — the main job (design §3): the song's audio with one track felt on the device. The player itself is
// host/player/; this file is the command line, the terminal and the messages.
#include <unistd.h>


#include <cmath>
#include <cstdio>

#include <fmt/format.h>

#include "host/audio/audio_events.hpp"
#include "host/audio/audio_player.hpp"
#include "host/cli/commands.hpp"
#include "host/cli/open_link.hpp"
#include "host/cli/play_view.hpp"
#include "host/cli/song_options.hpp"
#include "host/common/error.hpp"
#include "host/config/config.hpp"
#include "host/midi/gm.hpp"
#include "host/player/device_link.hpp"
#include "host/player/live_terminal.hpp"
#include "host/player/play_log.hpp"
#include "host/player/player.hpp"
#include "host/player/qemu_device.hpp"
#include "host/transport/device_spec.hpp"
#include "host/transport/handshake.hpp"
#include "host/transport/sim_transport.hpp"

namespace hmp::cli {

namespace {

struct PlayOptions {
  std::string song;
  std::optional<std::string> track;
  std::string device = "auto";
  AudioCliOptions audio;
  bool no_view = false;
  bool fullscreen = false;
  double speed = 1.0;
  std::optional<double> from_s, to_s;
  std::optional<std::string> log;
  bool force = false;
  HapticCliOptions haptic;
};

void check_window(const PlayOptions& o, const midi::Song& song) {
  for (const auto& t : {o.from_s, o.to_s}) {
    if (t && !(std::isfinite(*t) && *t >= 0)) throw BadInput("--from/--to: must be seconds ≥ 0");
  }
  if (o.from_s && *o.from_s >= song.duration_s()) {
    throw BadInput(fmt::format("--from {}: the song ends at {:.3f} s", *o.from_s, song.duration_s()));
  }
  if (o.to_s && *o.to_s <= o.from_s.value_or(0.0)) throw BadInput("--from/--to: empty window");
}

void print_summary(const player::Counters& c, const player::Snapshot& s, std::size_t window_notes, const std::string& device) {
  std::printf("%s\n",
              fmt::format("played {} of {} notes sent ({} in the window) of track {} \"{}\" on {}: late {}, stolen {}, "
                          "rejected {}{}{}; stopped at {}",
                          c.notes_played, c.notes_sent, window_notes, s.track, s.track_name, device, c.late, c.stolen,
                          c.rejected, c.skipped ? fmt::format(", skipped {}", c.skipped) : "",
                          c.recoveries ? fmt::format(", recovered {} time(s)", c.recoveries) : "",
                          format_time(s.song_us))
                  .c_str());
  std::fflush(stdout);
}

int run_play(const PlayOptions& o) {
  haptics::HapticOptions haptic = resolve(o.haptic);
  haptic.speed = o.speed;
  haptics::validate(haptic);
  // Refuse an existing log before any work (design §3: never overwrite without --force).
  player::PlayLog log;
  if (o.log) output::check_writable(*o.log, o.force);
  const audio::AudioOptions audio_opts = audio_options(o.audio);  // checks --soundfont, before any work

  const midi::ReadResult r = midi::load_song(o.song);
  for (const midi::Warning& w : r.warnings) warn_on_stderr(w.message);
  const midi::Song& song = r.song;
  check_window(o, song);
  const std::uint32_t track = o.track ? select_track(song, *o.track) : default_haptic_track(song);
  if (!o.track) {
    std::fprintf(stderr, "haptic track %s (the first with a Table 1 instrument; choose with --track or the t key)\n",
                 describe_track(song, track).c_str());
  }

  OpenedLink opened = open_link(o.device, haptic.tick_hz);
  if (!opened.note.empty()) std::fprintf(stderr, "%s\n", opened.note.c_str());
  player::DeviceLink link(*opened.transport, link_options_for(opened));
  const protocol::HelloReply hello = connect_and_describe(link, opened);
  if (o.haptic.tick_hz && *o.haptic.tick_hz != hello.tick_hz) {
    std::fprintf(stderr, "warning: the device ticks at %u Hz, not %u: notes are placed at %u Hz\n", hello.tick_hz,
                 *o.haptic.tick_hz, hello.tick_hz);
  }

  audio::AudioPlayer audio(audio_opts);
  audio.set_events(audio::audio_events(song));
  if (audio.audible()) {
    std::fprintf(stderr, "audio: %s, output latency %.1f ms (compensated)\n", audio.driver_name().c_str(),
                 audio.output_latency_s() * 1e3);
  }
  if (o.log) log = player::PlayLog(*o.log, true);  // checked above; it did not exist or --force was given

  const bool tty = isatty(STDERR_FILENO) && isatty(STDOUT_FILENO);
  player::RawKeys keys;
  player::StatusLine status(tty);
  player::install_stop_signals();

  player::PlayerOptions po;
  po.track = track;
  po.haptic = haptic;
  for (const std::string& path : o.haptic.config_paths) {
    // The config's [device] table: force of full scale and vibration direction (design §11).
    const config::Config cfg = config::load(path);
    if (cfg.peak_force_n) po.settings.peak_force_n = static_cast<float>(*cfg.peak_force_n);
    if (cfg.direction) {
      for (int i = 0; i < 3; ++i) po.settings.direction[i] = static_cast<float>((*cfg.direction)[static_cast<std::size_t>(i)]);
    }
  }
  po.from_us = o.from_s ? std::llround(*o.from_s * 1e6) : 0;
  if (o.to_s) po.to_us = std::llround(*o.to_s * 1e6);
  po.on_started = [&](const player::StartedNote& n) { log.started(n); };
  po.on_message = [&](const std::string& text) { status.message(text); };
  player::Player* running = nullptr;
  po.on_idle = [&] {
    if (player::stop_signal() != 0) running->post(player::Command::interrupt);
    while (auto key = keys.poll()) running->post(player::command_for(*key));
    status.show(running->snapshot());
    log.flush();
  };
  player::Player player(link, audio, song, po);
  running = &player;
  if (keys.active()) status.message("keys: space pause/resume, ←/→ seek 5 s, t/T track, e envelope, m mapping, [/] speed, q quit");
  // The animation (design §14): where there is no window to be had, one warning and the song plays on.
  std::unique_ptr<view::LiveView> window;
  if (!o.no_view) {
    haptics::HapticOptions strip = haptic;
    strip.tick_hz = hello.tick_hz;  // the strip shows what the device plays, at its rate
    std::string why;
    window = open_play_view(song, player, audio, strip,
                            {fmt::format("hmp — {}", o.song), opened.transport->name(), o.fullscreen}, why);
    if (!window) std::fprintf(stderr, "warning: no animation window: %s; the song plays on without it (--no-view: do not try)\n", why.c_str());
  }

  player::Outcome outcome = player::Outcome::finished;
  try {
    outcome = player.run();
  } catch (const player::LinkError&) {
    status.close();
    keys.restore();
    log.summary(player.counters());
    log.close();  // the log of a lost link is whole (summary included): kept, not removed as a cut write
    throw;
  }
  status.show(player.snapshot(), true);
  status.close();
  keys.restore();
  const player::Counters counters = player.counters();
  log.summary(counters);
  log.close();
  print_summary(counters, player.snapshot(), player.window_notes(), opened.transport->name());
  if (outcome == player::Outcome::interrupted) return 128 + player::stop_signal();  // as shells report a signal
  return kExitOk;
}

}  // namespace

void register_play(CLI::App& app, Registry& registry) {
  auto o = std::make_shared<PlayOptions>();
  CLI::App* cmd = app.add_subcommand("play", "Play a song with one track felt on the haptic device (the main job)");
  cmd->add_option("SONG", o->song, "MIDI file")->required();
  cmd->add_option("--track", o->track,
                  "Haptic track: index, or part of its name or instrument (default: the first with a Table 1 instrument)");
  cmd->add_option("--device", o->device, "auto (HID, else the simulated device), sim, qemu, hid[:VID:PID], serial:PATH")
      ->capture_default_str();
  add_audio_options(cmd, o->audio);
  cmd->add_flag("--no-view", o->no_view, "No animation window");
  cmd->add_flag("--fullscreen", o->fullscreen, "The animation window fills the screen (f toggles)");
  cmd->add_option("--speed", o->speed, "Playback speed 0.5–2 (sound and device follow; [ and ] change it while playing)")
      ->capture_default_str();
  cmd->add_option("--from", o->from_s, "Start of the passage in seconds of the song");
  cmd->add_option("--to", o->to_s, "End of the passage in seconds of the song");
  cmd->add_option("--log", o->log, "JSON lines: every note the device started, then a summary");
  cmd->add_flag("-f,--force", o->force, "Overwrite an existing log file");
  add_haptic_options(cmd, o->haptic);
  cmd->callback([o, &registry] { registry.set([o] { return run_play(*o); }); });
}

}  // namespace hmp::cli
