#pragma once
// The animation window of `hmp play` and `hmp view`: the view (host/view/live_view.hpp) wired to the
// player's clock, state and commands. Opening it never stops the song: when no window can be had, one
// warning says why and the caller goes on without it.
#include <memory>
#include <string>

#include "host/audio/audio_player.hpp"
#include "host/haptics/haptic_track.hpp"
#include "host/midi/song.hpp"
#include "host/player/player.hpp"
#include "host/view/live_view.hpp"

namespace hmp::cli {

struct PlayViewSetup {
  std::string title;        // the window's title
  std::string device_name;  // for the overlay
  bool fullscreen = false;
};

// `hmp play`: keys, clicks and the cursor go to the player; the overlay shows its snapshot.
std::unique_ptr<view::LiveView> open_play_view(const midi::Song& song, player::Player& player,
                                               audio::AudioPlayer& audio, const haptics::HapticOptions& haptic,
                                               const PlayViewSetup& setup, std::string& error);

// The legend's lines: "2 Flute (Flute)" per track with notes, "" for the others.
std::vector<std::string> legend_labels(const midi::Song& song);

}  // namespace hmp::cli
