#include "host/common/install_layout.hpp"

#include <cstdlib>
#include <fstream>
#include <system_error>

#include "shared/common/version.hpp"

namespace hmp::install {

namespace fs = std::filesystem;

fs::path program_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path{} : exe.parent_path();
}

std::optional<fs::path> source_tree() {
  if (const char* env = std::getenv("HMP_SOURCE_DIR"); env != nullptr && *env != '\0') return fs::path(env);
  const fs::path dir = program_dir();
  if (dir.empty()) return std::nullopt;
  std::ifstream marker(dir.parent_path() / "hmp-source-tree");
  std::string line;
  if (!marker || !std::getline(marker, line) || line.empty()) return std::nullopt;
  return fs::path(line);
}

fs::path data_dir() { return program_dir().parent_path() / "share" / "hmp"; }

fs::path example(std::string_view file) {
  const fs::path installed = data_dir() / "examples" / file;
  std::error_code ec;
  if (fs::is_regular_file(installed, ec)) return installed;
  if (const auto tree = source_tree()) {
    const fs::path in_tree = *tree / "examples" / file;
    if (fs::is_regular_file(in_tree, ec)) return in_tree;
  }
  return installed;
}

std::string version_text() {
  return std::to_string(version::kMajor) + "." + std::to_string(version::kMinor) + "." +
         std::to_string(version::kPatch);
}

std::string image_file_name(std::string_view board, std::string_view ext) {
  std::string name = "hmp_fw_";
  for (const char c : board) name += c == '-' ? '_' : c;
  return name + "-" + version_text() + std::string(ext);
}

fs::path installed_image(std::string_view board, std::string_view ext) {
  return data_dir() / "firmware" / image_file_name(board, ext);
}

}  // namespace hmp::install
