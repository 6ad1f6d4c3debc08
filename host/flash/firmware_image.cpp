// firmware_image: where a source tree's stm32f407 image is and whether it is older than its sources.
#include "host/flash/firmware_image.hpp"

#include <cstdint>
#include <fstream>
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

namespace {
// The STM32F407's memory (boards/stm32f407's linker script): 1 MiB of flash from 0x08000000, 128 KiB of
// SRAM from 0x20000000, 64 KiB of CCM RAM from 0x10000000.
constexpr std::uint32_t kFlashStart = 0x0800'0000, kFlashBytes = 1024 * 1024;
constexpr std::uint32_t kSramStart = 0x2000'0000, kSramBytes = 128 * 1024;
constexpr std::uint32_t kCcmStart = 0x1000'0000, kCcmBytes = 64 * 1024;

bool within(std::uint32_t address, std::uint32_t start, std::uint32_t bytes, bool end_inclusive) {
  return address >= start && (end_inclusive ? address - start <= bytes : address - start < bytes);
}
std::uint32_t word_le(const unsigned char* b) {
  return static_cast<std::uint32_t>(b[0]) | static_cast<std::uint32_t>(b[1]) << 8 |
         static_cast<std::uint32_t>(b[2]) << 16 | static_cast<std::uint32_t>(b[3]) << 24;
}
}  // namespace

std::string image_problem(const fs::path& image) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(image, ec);
  if (ec) return "cannot read it (" + ec.message() + ")";
  std::ifstream in(image, std::ios::binary);
  unsigned char head[20] = {};
  in.read(reinterpret_cast<char*>(head), sizeof head);
  const auto got = static_cast<std::size_t>(in.gcount());
  if (image.extension() == ".elf") {
    // e_ident: magic, ELFCLASS32 (1); e_machine at 18: EM_ARM (40), little-endian.
    const bool arm32 = got == sizeof head && head[0] == 0x7F && head[1] == 'E' && head[2] == 'L' && head[3] == 'F' &&
                       head[4] == 1 && head[18] == 40 && head[19] == 0;
    return arm32 ? "" : "not a 32-bit ARM ELF file";
  }
  if (size == 0) return "empty";
  if (size > kFlashBytes) return "larger than the board's 1 MiB of flash";
  if (got < 8) return "too short for a vector table";
  const std::uint32_t stack = word_le(head), reset = word_le(head + 4);
  const bool stack_ok = within(stack, kSramStart, kSramBytes, true) || within(stack, kCcmStart, kCcmBytes, true);
  const bool reset_ok = (reset & 1u) != 0 && within(reset & ~1u, kFlashStart, kFlashBytes, false);
  return stack_ok && reset_ok ? "" : "does not begin with an stm32f407 vector table";
}

}  // namespace hmp::flash
