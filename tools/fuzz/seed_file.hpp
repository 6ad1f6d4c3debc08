#pragma once
// What every seed-corpus writer (*_seeds.cpp) shares: its one argument, the output folder, and writing
// one seed file.
#include <cstddef>
#include <cstdio>
#include <fstream>
#include <string>

namespace hmp::fuzz {

// The output folder from `PROGRAM OUTPUT_DIR`; empty (after a usage line on stderr) when misused.
inline std::string seed_dir(int argc, char** argv) {
  if (argc == 2) return argv[1];
  std::fprintf(stderr, "usage: %s OUTPUT_DIR (must exist)\n", argv[0]);
  return {};
}

// Writes `size` bytes to `path`; false when the file could not be written whole.
inline bool write_seed_file(const std::string& path, const void* bytes, std::size_t size) {
  std::ofstream out(path, std::ios::binary);
  out.write(static_cast<const char*>(bytes), static_cast<std::streamsize>(size));
  return static_cast<bool>(out);
}

}  // namespace hmp::fuzz
