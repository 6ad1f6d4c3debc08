#pragma once
// firmware_image: the firmware image a source tree builds for a board (preset stm32f407), and whether it
// is out of date — missing, or older than a file it is built from (firmware/, shared/, boards/stm32f407/).
// Only reads the file system (modification times); building is the caller's (hmp flash).
#include <filesystem>
#include <string>

namespace hmp::flash {

// <source_dir>/build/stm32f407/boards/stm32f407/hmp_fw_stm32f407-VERSION.elf (elf) or .bin.
std::filesystem::path default_image(const std::filesystem::path& source_dir, bool elf);

// Whether the preset's build tree is configured (has a CMakeCache.txt).
bool build_configured(const std::filesystem::path& source_dir);

// The folders, relative to the source dir, whose files the stm32f407 image is built from, and the kinds
// of file that count (a README edited after the build does not make the image stale).
inline constexpr const char* kImageSourceDirs[] = {"firmware", "shared", "boards/stm32f407", "boards/cortex-m"};
bool is_build_input(const std::filesystem::path& file);  // sources, headers, linker scripts, CMake files

struct Freshness {
  bool stale = false;
  std::string why;  // when stale: "it does not exist" or "it is older than firmware/core.cpp"
};

// Stale when `image` does not exist or any build input under kImageSourceDirs of `source_dir` was
// modified after it. Folders that do not exist are skipped.
Freshness image_freshness(const std::filesystem::path& image, const std::filesystem::path& source_dir);

// Empty when `image` looks like an stm32f407 image of its kind; otherwise why not, for the user. A .bin
// must fit the 1 MiB of flash and begin with the vector table the boards/stm32f407 linker script puts
// there (the initial stack pointer in SRAM or CCM, a Thumb reset address in flash); an .elf must be a 32-bit
// ARM ELF. Cheap (reads 20 bytes), and what a flasher would otherwise write as given.
std::string image_problem(const std::filesystem::path& image);

}  // namespace hmp::flash
