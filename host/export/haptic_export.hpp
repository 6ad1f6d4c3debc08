#pragma once
// host/export/: the haptic track written for other players' haptic formats:
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
  double amplitude = 0;                // mapped amplitude / full scale, 0..1 (the engine's Q16 value)
  double sharpness = 0;                // mapped frequency placed linearly in [f_min, f_max], 0..1
};

struct ExportSpec {
  const haptics::HapticTrack* track = nullptr;
  const haptics::HapticOptions* opts = nullptr;
  std::uint64_t first_tick = 0, end_tick = 0;
  std::string title;  // what was rendered: "track 3 \"Flute\", mapping paper, envelope piano"
  std::string song;   // the song file as the user gave it (a path, perhaps); empty when there is none
};

// The notes sounding in [first_tick, end_tick), clipped to it.
std::vector<ExportNote> export_notes(const ExportSpec& spec);

// The song's file name without its directories: the path as typed says where the user keeps files, which
// a file handed to others has no business carrying. The description is that name, " — ", the title.
std::string song_file_name(const ExportSpec& spec);
std::string export_description(const ExportSpec& spec);

// The note's envelope as the device evaluates it (its preset: built-in, or the user preset of its slot).
envelope::Envelope note_envelope(const haptics::HapticTrack& t, const haptics::HapticOptions& o, const synth::Note& n);

// Writes path (.ahap or .haptic, chosen by extension); throws BadInput for another extension, and for a
// window in which no note of the track sounds (nothing would play: refused, nothing written).
void write_haptic_export(const std::string& path, bool force, const ExportSpec& spec);
bool is_haptic_export(const std::string& path);

}  // namespace hmp::exporting
