#pragma once
// Settings of the song's audio (design §14), shared by the live player and the offline renderer.
#include <functional>
#include <string>
#include <vector>

#include "host/audio/synth_settings.hpp"

namespace hmp::audio {

// Where warnings go (one line each, no "warning:" prefix). The default prints "warning: …" on stderr.
using WarningSink = std::function<void(const std::string&)>;
void print_warning(const std::string& message);

struct AudioOptions {
  bool enabled = true;    // false (`--no-audio`): no SoundFont is loaded and no audio driver is created
  std::string soundfont;  // a .sf2/.sf3 path; empty: the standard places (soundfont.hpp)
  // FluidSynth drivers, tried in order; "virtual" is a simulated card (never tried unless named).
  std::vector<std::string> drivers = {"pulseaudio", "alsa", "sdl2"};
  SynthSettings synth;
  // Driver buffering: frames per period and number of periods. The output latency estimate is
  // period_frames × periods / sample_rate (5.3 ms × 4 = 21 ms at 48 kHz by default).
  int period_frames = 256;
  int periods = 4;
  // The "virtual" driver (virtual_card.hpp, for measurements): its crystal error, how many frames of its
  // output it keeps, and the period it chooses itself as JACK and PipeWire do (0: the one asked for).
  double virtual_ppm = 0.0;
  std::size_t virtual_record_frames = 0;
  int virtual_period_frames = 0;
};

}  // namespace hmp::audio
