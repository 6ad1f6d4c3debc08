#pragma once
// Where hmp finds the files it ships, with no path of the build machine compiled in. The program looks
// relative to itself (/proc/self/exe):
//   installed    <prefix>/bin/hmp, the modules in <prefix>/lib/hmp/, data in <prefix>/share/hmp/
//                (examples/, firmware/)
//   build tree   <build>/bin/hmp, <build>/lib/hmp/, and <build>/hmp-source-tree, a file CMake writes
//                at configure time naming the source tree (never installed)
// An installed hmp uses its share/hmp/; one run from a build tree uses that tree's sources.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace hmp::install {

// The folder of the running program; empty where /proc/self/exe cannot be read.
std::filesystem::path program_dir();

// The source tree this hmp was built in: $HMP_SOURCE_DIR when set and not empty, else the path that
// <program_dir>/../hmp-source-tree names when that file exists (a build tree). nullopt for an
// installed hmp. The path is not checked for being a source tree.
std::optional<std::filesystem::path> source_tree();

// <program_dir>/../share/hmp: an installed hmp's data.
std::filesystem::path data_dir();

// An example song shipped with hmp (`file` names it, e.g. "pedal-demo.mid"): the installed copy when it
// exists, else the one in the source tree's examples folder, else the installed path (which the caller
// reports as missing).
std::filesystem::path example(std::string_view file);

// The project's version, "MAJOR.MINOR.PATCH" (project(VERSION …) in CMakeLists.txt).
std::string version_text();

// The file name of a shipped firmware image: hmp_fw_<board>-<version><ext>, board with '-' as '_'
// ("stm32f407", ".elf" → "hmp_fw_stm32f407-0.1.0.elf"). The cross trees name their images the same way
// (boards/*/CMakeLists.txt).
std::string image_file_name(std::string_view board, std::string_view ext);

// <data_dir>/firmware/<image_file_name(board, ext)>: where an installed hmp's image is.
std::filesystem::path installed_image(std::string_view board, std::string_view ext);

}  // namespace hmp::install
