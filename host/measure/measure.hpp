#pragma once
// `hmp envelope measure`'s work: one note of each GM program rendered by FluidSynth from a SoundFont,
// its envelope measured and fitted (sound_envelope.hpp). The notes share one render (one SoundFont
// load); a note that has died away before its release is rendered again, released while still loud, so
// that its release can be measured too.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "host/measure/sound_envelope.hpp"

namespace hmp::measure {

struct MeasureOptions {
  std::string soundfont;  // a path (checked by the caller)
  std::vector<std::uint8_t> programs;
  std::uint8_t key = 60;     // middle C
  bool key_fallback = true;  // a program silent at `key` is tried 1–2 octaves away
  std::uint8_t velocity = 100;
  double hold_s = 2.5;            // note-on to note-off
  double release_window_s = 2.5;  // measured after the note-off
};

struct Measured {
  std::uint8_t program = 0;
  std::uint8_t key = 0;  // the key it sounded at
  SoundEnvelope held;    // the note held for hold_s
  Stages stages;
  envelope::Adsr preset;  // Eq. 9–10 fitted
  double rms_error = 0;   // of the preset against the sound, full scale = the sound's peak
  bool release_from_second_render = false;
};

// Throws BadInput when the SoundFont cannot be rendered. `progress` hears each pass as it starts.
std::vector<Measured> measure_programs(const MeasureOptions& options,
                                       const std::function<void(const std::string&)>& progress = {});

// The frequency of a MIDI key (A4 = key 69 = 440 Hz).
double key_hz(std::uint8_t key);

}  // namespace hmp::measure
