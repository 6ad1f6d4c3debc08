#pragma once
// `hmp render SONG --sound --out FILE.wav`: the song's own sound rendered offline (all tracks, with their
// controllers; FluidSynth at 44.1 kHz stereo). Not `--audible`, which makes one track's haptic signal
// listenable.
#include <optional>
#include <string>

namespace hmp::cli {

struct SoundRenderRequest {
  std::string song, out;
  std::optional<double> from_s, to_s;
  std::optional<std::string> soundfont;
  bool force = false;
};

// Renders and writes the WAV; BadInput (exit 2) for what cannot work, checked before any work.
void run_sound_render(const SoundRenderRequest& r);

// Seconds of sound kept after the song's last event, without --to or with one past them: releases and
// reverb tails.
inline constexpr double kSoundTailS = 2.0;

}  // namespace hmp::cli
