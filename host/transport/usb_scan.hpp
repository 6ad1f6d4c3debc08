#pragma once
// usb_scan: the boards on the USB bus that are not (yet) our HID device — an STM32 waiting in its ROM DFU
// bootloader, an ST-LINK probe — which `hmp devices` lists and `hmp flash` writes through. The looking is
// done by the usb module (libusb). A machine without USB access (a container, no /dev/bus/usb) has none:
// that is an empty list and a reason, never an error.
#include <cstdint>
#include <string>
#include <vector>

namespace hmp::transport {

enum class ProbeKind { stm32_dfu, stlink };

struct UsbId {
  std::uint16_t vid, pid;
  ProbeKind kind;
  const char* name;
};

// What we look for: the STM32's ROM bootloader in DFU mode, and ST-LINK probes (V2, V2-1, V3 variants).
inline constexpr UsbId kKnownIds[] = {
    {0x0483, 0xdf11, ProbeKind::stm32_dfu, "STM32 in DFU mode"}, {0x0483, 0x3748, ProbeKind::stlink, "ST-LINK/V2"},
    {0x0483, 0x374a, ProbeKind::stlink, "ST-LINK/V2-1"},         {0x0483, 0x374b, ProbeKind::stlink, "ST-LINK/V2-1"},
    {0x0483, 0x3752, ProbeKind::stlink, "ST-LINK/V2-1"},         {0x0483, 0x374e, ProbeKind::stlink, "ST-LINK/V3"},
    {0x0483, 0x374f, ProbeKind::stlink, "ST-LINK/V3"},           {0x0483, 0x3753, ProbeKind::stlink, "ST-LINK/V3"},
    {0x0483, 0x3754, ProbeKind::stlink, "ST-LINK/V3"},
};

// The entry for a VID:PID, or null.
const UsbId* known_id(std::uint16_t vid, std::uint16_t pid);

struct FoundProbe {
  ProbeKind kind;
  std::string name;
  int bus = 0, address = 0;
};

struct ScanResult {
  std::vector<FoundProbe> found;
  std::string unavailable;  // why USB could not be looked at (empty: it was)
};

ScanResult scan_usb();

// One line for `hmp devices`: "STM32 in DFU mode on bus 1 device 5 — run hmp flash".
std::string describe(const FoundProbe& probe);

}  // namespace hmp::transport
