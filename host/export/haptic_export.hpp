#pragma once
// host/export/: the haptic track written for other players' haptic formats (issue 16 item 2):
// .ahap (Apple Core Haptics) and .haptic (Meta Haptics Studio), both JSON via nlohmann-json.
// This header owns the format-independent part: the notes of the window with their mapped intensity and
// sharpness, and each note's envelope as the device evaluates it.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "host/haptics/haptic_track.hpp"
#include "shared/envelope/envelope.hpp"

namespace hmp::exporting {

struct ExportNote {
  double start_s = 0, duration_s = 0;  // clipped to the window, start relative to the window's start
  double intensity = 0;                // mapped amplitude / full scale, 0..1
  double sharpness = 0;                // mapped frequency placed linearly in [f_min, f_max], 0..1
};

struct ExportSpec {
  const haptics::HapticTrack* track = nullptr;
  const haptics::HapticOptions* opts = nullptr;
  std::uint64_t first_tick = 0, end_tick = 0;
  std::string title;
};

// The notes sounding in [first_tick, end_tick), clipped to it.
std::vector<ExportNote> export_notes(const ExportSpec& spec);

// The note's envelope as the device evaluates it (its preset: built-in, or the user preset of its slot).
envelope::Envelope note_envelope(const haptics::HapticTrack& t, const haptics::HapticOptions& o,
                                 const synth::Note& n);

// Writes path (.ahap or .haptic, chosen by extension); throws BadInput for another extension.
void write_haptic_export(const std::string& path, bool force, const ExportSpec& spec);
bool is_haptic_export(const std::string& path);

}  // namespace hmp::exporting
