#pragma once
// Process-wide set-up around FluidSynth that no single object owns:
//  - FluidSynth's log goes to a capture buffer instead of stderr (its errors become part of our one
//    warning; its info and debug lines are dropped), and alsa-lib's own stderr messages are silenced,
//    so a machine without a sound card plays silently without a screenful of noise (design §14);
//  - a count of audio-driver attempts, so tests can prove `--no-audio` never touches a sound device.
#include <cstdint>
#include <string>
#include <vector>

namespace hmp::audio {

// Idempotent; every FluidSynth user in hmp calls it before creating settings.
void install_fluid_logging();

// Errors and warnings FluidSynth logged since the last call (oldest first), and clears them.
std::vector<std::string> take_fluid_messages();

// Audio drivers hmp has tried to open since the program started (successful or not).
std::uint64_t fluid_driver_attempts();
void count_audio_driver_attempt();

// FluidSynth's sdl2 driver needs the program to have initialised SDL's audio subsystem. Returns false
// (nothing to undo) when SDL has no audio backend at all.
bool sdl_audio_acquire();
void sdl_audio_release();

}  // namespace hmp::audio
