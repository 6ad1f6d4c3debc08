#pragma once
// Opening files the user named for output, without ever overwriting one silently: an existing file is
// replaced only with --force, or after a "yes" when we can ask on a terminal.
#include <cstdio>
#include <memory>
#include <string>

namespace hmp::output {

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f && f != stdout) std::fclose(f);
  }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

// Checks that `path` may be written (throws BadInput otherwise). "-" means standard output.
void check_writable(const std::string& path, bool force);
// check_writable + fopen in binary mode. "-" returns stdout.
FilePtr open_for_writing(const std::string& path, bool force);
// Lower-case extension without the dot ("csv", "wav", "png"), or "" if none.
std::string extension_of(const std::string& path);

}  // namespace hmp::output
