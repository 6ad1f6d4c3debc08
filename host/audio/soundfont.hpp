#pragma once
// Where the General MIDI SoundFont is (design §14: Debian's fluid-soundfont-gm).
#include <optional>
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

}  // namespace hmp::audio
