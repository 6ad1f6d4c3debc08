#pragma once
// host/export/: the haptic track written for other players' haptic formats (issue 16 item 2):
// .ahap (Apple Core Haptics) and .haptic (Meta Haptics Studio), both JSON via nlohmann-json.
// This header owns the format-independent part: each note's envelope sampled into breakpoints.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "host/haptics/haptic_track.hpp"
#include "shared/envelope/envelope.hpp"

namespace hmp::exporting {

// One envelope breakpoint of a note: time in seconds from the note's start, level relative to the note's
// peak (0..1). Linear interpolation between consecutive points approximates the envelope.
struct Breakpoint {
  double t_s = 0;
  double level = 0;
};

struct ExportNote {
  double start_s = 0, duration_s = 0;  // clipped to the window, start relative to the window's start
  double intensity = 0;                // mapped amplitude / full scale, 0..1
  double sharpness = 0;                // mapped frequency placed linearly in [f_min, f_max], 0..1
  std::vector<Breakpoint> envelope;    // relative to start_s
};

struct ExportSpec {
  const haptics::HapticTrack* track = nullptr;
  const haptics::HapticOptions* opts = nullptr;
  std::uint64_t first_tick = 0, end_tick = 0;
  std::string title;
};

// The notes sounding in [first_tick, end_tick), envelopes sampled every `step_ticks` ticks plus the
// note's last tick (each point is the device's envelope value at that tick).
std::vector<ExportNote> export_notes(const ExportSpec& spec, std::uint32_t step_ticks);

// The note's envelope as the device evaluates it (its preset: built-in, or the user preset of its slot).
envelope::Envelope note_envelope(const haptics::HapticTrack& t, const haptics::HapticOptions& o,
                                 const synth::Note& n);

// Writes path (.ahap or .haptic, chosen by extension); throws BadInput for another extension.
void write_haptic_export(const std::string& path, bool force, const ExportSpec& spec);
bool is_haptic_export(const std::string& path);

}  // namespace hmp::exporting
