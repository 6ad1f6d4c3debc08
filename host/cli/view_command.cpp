// hmp view SONG [--track T] [--from S] [--to S] [--no-audio] … — the animation with the song's audio and
// no device (design §14): the window of `hmp play` driven by the audio clock alone. Keys and clicks
// pause, seek and choose the haptic track (the blue one, whose signal the strip shows).
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <deque>
#include <mutex>
#include <thread>

#include <fmt/format.h>

#include "host/audio/audio_events.hpp"
#include "host/audio/audio_player.hpp"
#include "host/cli/commands.hpp"
#include "host/cli/play_view.hpp"
#include "host/cli/song_options.hpp"
#include "host/common/error.hpp"
#include "host/common/song_window.hpp"
#include "host/haptics/signal_tail.hpp"
#include "host/player/live_terminal.hpp"

namespace hmp::cli {

namespace {

struct ViewOptions {
  std::string song;
  std::optional<std::string> track;
  AudioCliOptions audio;
  std::optional<double> from_s, to_s;
  bool fullscreen = false;
  double speed = 1.0;
  HapticCliOptions haptic;
};

// What the window asked for, handed from its thread to the main loop.
struct Requests {
  std::mutex mutex;
  std::deque<player::Key> keys;
  std::optional<std::int64_t> seek_us;
  std::optional<std::uint32_t> track;
};

int run_view(const ViewOptions& o) {
  haptics::HapticOptions haptic = resolve(o.haptic);
  haptic.speed = o.speed;
  haptics::validate(haptic);
  const audio::AudioOptions audio_opts = audio_options(o.audio);  // checks --soundfont, before any work
  const midi::ReadResult r = midi::load_song(o.song);
  const midi::Song& song = r.song;
  SongWindowUs passage;
  std::uint32_t track = 0;
  haptics::check_song_then_warn(r, warn_on_stderr, [&] {
    passage = song_window(o.from_s, o.to_s, song.duration_us);
    track = o.track ? select_track(song, *o.track) : default_haptic_track(song);
  });
  const std::int64_t begin_us = passage.begin_us, end_us = passage.end_us;  // lambdas below capture them

  audio::AudioPlayer audio(audio_opts);
  audio.set_events(audio::audio_events(song));

  std::mutex strip_mutex;  // the haptic track whose signal the strip shows
  auto build = [&](std::uint32_t t) {
    return std::make_shared<haptics::SignalTail>(
        std::make_shared<const haptics::HapticTrack>(haptics::build_haptic_track(song, t, haptic)), haptic);
  };
  std::shared_ptr<haptics::SignalTail> strip = build(track);
  std::atomic<std::uint32_t> shown_track{track};
  std::atomic<bool> paused{false};
  Requests requests;
  const std::uint32_t tracks = static_cast<std::uint32_t>(song.tracks.size());

  view::LiveViewOptions options;
  options.setup.title = fmt::format("hmp view — {}", o.song);
  options.setup.fullscreen = o.fullscreen;
  options.track_labels = legend_labels(song);
  options.help = {"space  pause / resume          \u2190 \u2192  seek 5 s    q / Esc  quit",
                  "t / T  next / previous track    [ / ]  speed", "click or drag the bar at the bottom: seek",
                  "click a track in the legend: show / hide it",
                  "hold the button 0.5 s on a note: make its track the haptic one (the strip shows its vibration)"};
  view::LiveViewHooks hooks;
  hooks.song_time = [&audio](view::Clock::time_point t) { return audio.song_time_us(t); };
  hooks.state = [&] {
    view::LiveState st;
    st.haptic_track = shown_track.load();
    st.paused = paused.load();
    st.begin_us = begin_us;
    st.end_us = end_us;
    const midi::Track& t = song.tracks[st.haptic_track];
    const double speed = audio.speed();
    st.overlay =
        fmt::format("{}  {} / {}{}   track {} \"{}\"   audio {}   no device   (h: help)",
                    st.paused ? "paused" : "playing", format_time(audio.song_time_us()), format_time(end_us),
                    speed != 1.0 ? fmt::format("   speed {:g}×", speed) : "", t.index, t.name, audio.driver_name());
    return st;
  };
  hooks.key = [&](char k) {
    const auto key = player::key_for_char(k);
    if (!key) return;
    std::lock_guard lock(requests.mutex);
    requests.keys.push_back(*key);
  };
  hooks.seek_to = [&](std::int64_t us) {
    std::lock_guard lock(requests.mutex);
    requests.seek_us = us;
  };
  hooks.select_track = [&](std::uint32_t t) {
    std::lock_guard lock(requests.mutex);
    requests.track = t;
  };
  hooks.vibration = [&](std::int64_t song_us, float* out, int max) {
    std::shared_ptr<haptics::SignalTail> s;
    {
      std::lock_guard lock(strip_mutex);
      s = strip;
    }
    return s->samples(song_us, out, max);
  };
  std::string why;
  const std::unique_ptr<view::LiveView> window = view::LiveView::open(song, std::move(options), std::move(hooks), why);
  if (!window) {
    std::fprintf(stderr, "error: no animation window: %s\n", why.c_str());
    return kExitFailure;
  }
  std::fprintf(stderr, "view: %s, audio %s; h in the window lists the keys\n", window->renderer().c_str(),
               audio.driver_name().c_str());

  player::RawKeys keys;
  player::install_stop_signals();
  audio.set_speed(o.speed);
  audio.start(begin_us);
  auto switch_to = [&](std::uint32_t t) {
    if (t >= tracks || song.tracks[t].note_count == 0) return;
    std::shared_ptr<haptics::SignalTail> s = build(t);
    std::lock_guard lock(strip_mutex);
    strip = std::move(s);
    shown_track = t;
  };
  auto step_track = [&](int dir) {
    for (std::uint32_t i = 1; i <= tracks; ++i) {
      const std::uint32_t t = (shown_track.load() + tracks + static_cast<std::uint32_t>(dir) * i) % tracks;
      if (song.tracks[t].note_count > 0) return switch_to(t);
    }
  };
  auto seek = [&](std::int64_t us) { audio.seek(std::clamp<std::int64_t>(us, begin_us, end_us)); };
  int rc = kExitOk;
  for (;;) {
    std::deque<player::Key> pending;
    std::optional<std::int64_t> seek_us;
    std::optional<std::uint32_t> wanted;
    {
      std::lock_guard lock(requests.mutex);
      pending.swap(requests.keys);
      seek_us.swap(requests.seek_us);
      wanted.swap(requests.track);
    }
    while (auto k = keys.poll()) pending.push_back(*k);
    bool quit = window->closed() || player::stop_signal() != 0;
    if (player::stop_signal() != 0) rc = 128 + player::stop_signal();
    if (seek_us) seek(*seek_us);
    if (wanted) switch_to(*wanted);
    for (const player::Key k : pending) {
      using player::Command;
      switch (const Command c = player::command_for(k)) {
        case Command::toggle_pause:
          if (paused.exchange(!paused.load()))
            audio.resume();
          else
            audio.pause();
          break;
        case Command::seek_back: seek(audio.song_time_us() - 5'000'000); break;
        case Command::seek_forward: seek(audio.song_time_us() + 5'000'000); break;
        case Command::next_track: step_track(1); break;
        case Command::previous_track: step_track(-1); break;
        case Command::quit: quit = true; break;
        case Command::slower:
        case Command::faster: audio.set_speed(player::next_speed(audio.speed(), c == Command::faster ? 1 : -1)); break;
        default: break;  // envelope and mapping change what a device plays: hmp view has none
      }
    }
    if (quit || (!paused && audio.song_time_us() >= end_us)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  audio.stop();
  keys.restore();
  return rc;
}

}  // namespace

void register_view(CLI::App& app, Registry& registry) {
  auto o = std::make_shared<ViewOptions>();
  CLI::App* cmd = app.add_subcommand("view", "The animation with the song's audio, no device");
  cmd->add_option("SONG", o->song, "MIDI file")->required();
  cmd->add_option("--track", o->track, "The haptic track shown in front (default: as hmp play chooses)");
  add_audio_options(cmd, o->audio);
  cmd->add_option("--from", o->from_s, "Start in seconds of the song");
  cmd->add_option("--to", o->to_s, "End in seconds of the song");
  cmd->add_flag("--fullscreen", o->fullscreen, "Fill the screen (f toggles)");
  cmd->add_option("--speed", o->speed, "Playback speed 0.5–2 ([ and ] change it)")->capture_default_str();
  add_haptic_options(cmd, o->haptic);
  cmd->callback([o, &registry] { registry.set([o] { return run_view(*o); }); });
}

}  // namespace hmp::cli
