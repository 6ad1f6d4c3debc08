#pragma once
// Where the General MIDI SoundFont is (design §14: Debian's fluid-soundfont-gm).
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace hmp::audio {

// The standard places, in the order they are searched.
const std::vector<std::string>& standard_soundfont_paths();

// An explicit path is used as given (nullopt when it is not a readable file: the caller warns instead
// of silently picking another one); an empty one means the first readable standard path.
std::optional<std::string> find_soundfont(const std::string& explicit_path = "");

// Empty when the file starts like a SoundFont 2/3 ("RIFF" … "sfbk"); otherwise why not. Checked before
// FluidSynth sees a file: its fallback loader (libinstpatch) prints GLib criticals on stderr for
// files it cannot parse either.
std::string soundfont_format_problem(const std::string& path);

// The programs (0–127) a SoundFont has presets for in `bank` (0: the melodic GM bank), read from its
// preset headers; empty when the file cannot be read as one. FluidSynth plays some other preset for a
// program the file lacks, so only this tells that the program is not there.
std::set<std::uint8_t> soundfont_programs(const std::string& path, std::uint16_t bank = 0);

}  // namespace hmp::audio
