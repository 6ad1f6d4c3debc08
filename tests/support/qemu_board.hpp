#pragma once
// Whether `hmp … --device qemu[:net]` can run here: the qemu-an386 image where hmp looks for it
// ($HMP_QEMU_ELF, else the source tree's qemu-an386 tree) and the emulator ($QEMU_SYSTEM_ARM, else
// qemu-system-arm on the PATH). Tests that need both skip with the reason.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>

#include "host/transport/qemu_device.hpp"

namespace hmp::test {

// Empty when both are there; otherwise what is missing, for GTEST_SKIP.
inline std::string qemu_board_missing() {
  namespace fs = std::filesystem;
  const std::string image = transport::find_qemu_image();
  std::error_code ec;
  if (image.empty() || !fs::exists(image, ec)) return "no qemu-an386 firmware image (cmake --preset qemu-an386)";
  const std::string emulator = transport::qemu_emulator();
  if (emulator.find('/') != std::string::npos) {
    return ::access(emulator.c_str(), X_OK) == 0 ? "" : emulator + " is not executable";
  }
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path != nullptr ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    if (!dir.empty() && ::access((dir + "/" + emulator).c_str(), X_OK) == 0) return "";
  }
  return emulator + " is not installed";
}

}  // namespace hmp::test
