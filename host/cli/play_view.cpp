#include "host/cli/play_view.hpp"

#include <chrono>
#include <mutex>

#include <fmt/format.h>

#include "host/haptics/signal_tail.hpp"
#include "host/midi/gm.hpp"
#include "host/player/live_terminal.hpp"

namespace hmp::cli {

std::vector<std::string> legend_labels(const midi::Song& song) {
  std::vector<std::string> labels;
  for (const midi::Track& t : song.tracks) {
    labels.push_back(t.note_count == 0 ? ""
                                       : fmt::format("{} {} ({})", t.index, t.name.empty() ? "—" : t.name,
                                                     midi::gm_instrument_name(t.program(), t.channel())));
  }
  return labels;
}

namespace {
constexpr auto kMessageShown = std::chrono::seconds(4);  // how long a player's message stays on the top line
}  // namespace

std::unique_ptr<view::LiveView> open_play_view(const midi::Song& song, player::Player& player,
                                               audio::AudioPlayer& audio, const haptics::HapticOptions& haptic,
                                               const PlayViewSetup& setup, std::string& error) {
  view::LiveViewOptions options;
  options.setup.title = setup.title;
  options.setup.fullscreen = setup.fullscreen;
  options.track_labels = legend_labels(song);
  options.help = {"space  pause / resume          \u2190 \u2192  seek 5 s    q / Esc  quit",
                  "t / T  next / previous track    e  envelope    m  mapping    [ / ]  speed",
                  "n / p  next / previous song (a playlist)",
                  "click or drag the bar at the bottom: seek",
                  "click a track in the legend: show / hide it",
                  "the cursor on a note: feel it;  hold the button 0.5 s: make its track the haptic one"};

  // The strip's signal follows the haptic track the player sends (rebuilt on a switch, on the view's thread).
  struct Strip {
    std::mutex mutex;
    std::unique_ptr<haptics::SignalTail> tail;
  };
  auto strip = std::make_shared<Strip>();
  const std::string device = setup.device_name;

  view::LiveViewHooks hooks;
  hooks.song_time = [&audio](view::Clock::time_point t) { return audio.song_time_us(t); };
  hooks.state = [&player, device] {
    const player::Snapshot s = player.snapshot();
    view::LiveState st;
    st.haptic_track = s.track;
    st.paused = s.paused;
    st.begin_us = s.begin_us;
    st.end_us = s.end_us;
    st.grip_m = s.grip_m;
    st.overlay = fmt::format(
        "{}{}  {} / {}{}   track {} \"{}\"   envelope {}   mapping {}   {}   late {}  stolen {}   (h: help)",
        s.song_label.empty() ? "" : s.song_label + "   ", player::state_word(s), format_time(s.song_us),
        format_time(s.end_us), s.speed != 1.0 ? fmt::format("   speed {:g}×", s.speed) : "", s.track, s.track_name,
        s.envelope, s.mapping, device, s.counters.late, s.counters.stolen);
    // What the terminal prints (a track switched, the device lost or back, a touch refused), for a while.
    if (!s.message.empty() && std::chrono::steady_clock::now() - s.message_at < kMessageShown)
      st.overlay += "     " + s.message;
    return st;
  };
  hooks.key = [&player](char k) {
    if (const auto key = player::key_for_char(k)) player.post(player::command_for(*key));
  };
  hooks.seek_to = [&player](std::int64_t us) { player.seek_to(us); };
  hooks.touch = [&player](const view::Bar& b) { player.touch(b.track, b.key, static_cast<double>(b.start_us) / 1e6); };
  hooks.select_track = [&player](std::uint32_t t) { player.select_track(t); };
  hooks.vibration = [&player, strip, haptic](std::int64_t song_us, float* out, int max) {
    const std::shared_ptr<const haptics::HapticTrack> now = player.snapshot().haptic;
    std::lock_guard lock(strip->mutex);
    if (!strip->tail || strip->tail->track() != now.get())
      strip->tail = std::make_unique<haptics::SignalTail>(now, haptic);
    return strip->tail->samples(song_us, out, max);
  };
  return view::LiveView::open(song, std::move(options), std::move(hooks), error);
}

}  // namespace hmp::cli
