#pragma once
// The project's version. It is written in one place, project(VERSION …) in the top CMakeLists.txt, which
// passes it to every tree (host and firmware) as HMP_VERSION_MAJOR/MINOR/PATCH: the program's --version,
// the firmware's HelloReply and the USB device's bcdDevice all come from here.
#include <cstdint>

namespace hmp::version {

#if !defined(HMP_VERSION_MAJOR) || !defined(HMP_VERSION_MINOR) || !defined(HMP_VERSION_PATCH)
#error "HMP_VERSION_MAJOR/MINOR/PATCH come from project(VERSION …) (CMakeLists.txt)"
#endif

inline constexpr std::uint8_t kMajor = HMP_VERSION_MAJOR, kMinor = HMP_VERSION_MINOR, kPatch = HMP_VERSION_PATCH;

// USB's binary-coded decimal release number 0xJJMN for major JJ, minor M, patch N (each part below 10
// but the major, below 100).
constexpr std::uint16_t usb_bcd() {
  return static_cast<std::uint16_t>((kMajor / 10) << 12 | (kMajor % 10) << 8 | (kMinor % 10) << 4 | (kPatch % 10));
}
static_assert(kMajor < 100 && kMinor < 10 && kPatch < 10, "the version must fit USB's bcdDevice (JJ.M.N)");

}  // namespace hmp::version
