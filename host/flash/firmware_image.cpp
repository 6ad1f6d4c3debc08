// firmware_image: where a source tree's stm32f407 image is and whether it is older than its sources.
#include "host/flash/firmware_image.hpp"

#include <system_error>

#include "host/common/install_layout.hpp"

namespace hmp::flash {

namespace fs = std::filesystem;

fs::path default_image(const fs::path& source_dir, bool elf) {
  return source_dir / "build" / "stm32f407" / "boards" / "stm32f407" /
         install::image_file_name("stm32f407", elf ? ".elf" : ".bin");
}

bool build_configured(const fs::path& source_dir) {
  std::error_code ec;
  return fs::is_regular_file(source_dir / "build" / "stm32f407" / "CMakeCache.txt", ec);
}

bool is_build_input(const fs::path& file) {
  const std::string ext = file.extension().string();
  return ext == ".cpp" || ext == ".hpp" || ext == ".h" || ext == ".c" || ext == ".ld" || ext == ".cmake" ||
         ext == ".in" || file.filename() == "CMakeLists.txt";
}

Freshness image_freshness(const fs::path& image, const fs::path& source_dir) {
  std::error_code ec;
  const fs::file_time_type built = fs::last_write_time(image, ec);
  if (ec) return {true, "it does not exist"};
  for (const char* dir : kImageSourceDirs) {
    const fs::path root = source_dir / dir;
    if (!fs::is_directory(root, ec)) continue;
    for (auto it = fs::recursive_directory_iterator(root, fs::directory_options::skip_permission_denied, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
      std::error_code file_ec;
      if (!it->is_regular_file(file_ec) || !is_build_input(it->path())) continue;
      const fs::file_time_type changed = it->last_write_time(file_ec);
      if (!file_ec && changed > built) {
        return {true, "it is older than " + fs::relative(it->path(), source_dir, file_ec).generic_string()};
      }
    }
  }
  return {};
}

}  // namespace hmp::flash
