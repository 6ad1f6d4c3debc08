#include "host/output/output_file.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <iostream>

#include "host/common/error.hpp"

namespace hmp::output {

namespace fs = std::filesystem;

namespace {
bool ask_yes(const std::string& question) {
  if (!isatty(STDIN_FILENO) || !isatty(STDERR_FILENO)) return false;
  std::cerr << question << " [y/N] " << std::flush;
  std::string answer;
  if (!std::getline(std::cin, answer)) return false;
  return !answer.empty() && (answer[0] == 'y' || answer[0] == 'Y');
}
}  // namespace

std::string extension_of(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  std::string lower = ext.empty() ? "" : ext.substr(1);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return lower;
}

void check_writable(const std::string& path, bool force) {
  if (path == "-") return;
  std::error_code ec;
  const fs::path p(path);
  if (fs::is_directory(p, ec)) throw BadInput(path + ": is a directory");
  const fs::path parent = p.has_parent_path() ? p.parent_path() : fs::path(".");
  if (!fs::is_directory(parent, ec)) throw BadInput(path + ": folder " + parent.string() + " does not exist");
  if (fs::exists(p, ec) && !force && !ask_yes(path + " exists. Overwrite?")) {
    throw BadInput(path + ": file exists (use --force to overwrite)");
  }
}

FilePtr open_for_writing(const std::string& path, bool force) {
  if (path == "-") return FilePtr(stdout);
  check_writable(path, force);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw BadInput(path + ": cannot open for writing");
  return FilePtr(f);
}

}  // namespace hmp::output
