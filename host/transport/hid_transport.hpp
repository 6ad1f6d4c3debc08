#pragma once
// USB HID link (design §9, §14) through hidapi's hidraw backend: the device's vendor-defined interface
// (usage page 0xFF00) with one 64-byte input and one 64-byte output report, no report IDs. Each
// interrupt transfer is one report, so there is no framing.
//
// On Linux the /dev/hidrawN nodes belong to root unless a udev rule opens them to users; docs/host.md
// has the rule. Enumeration reads sysfs only and works without it.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "host/transport/transport.hpp"

namespace hmp::transport {

struct HidId {
  std::uint16_t vid = protocol::kUsbVid;
  std::uint16_t pid = protocol::kUsbPid;
  friend bool operator==(const HidId&, const HidId&) = default;
};
std::string to_string(const HidId& id);  // "1209:0001"
// "1209:0001" (hex, optional 0x prefixes) → id; throws hmp::BadInput naming the text otherwise.
HidId parse_hid_id(std::string_view text);

struct HidDeviceInfo {
  std::string path;  // /dev/hidrawN
  HidId id;
  std::uint16_t release = 0;  // bcdDevice
  std::string serial;         // may be empty (devices without a serial string)
  std::string manufacturer;
  std::string product;
  std::uint16_t usage_page = 0;
  std::uint16_t usage = 0;
  int interface_number = -1;
};

// The connected devices with this VID:PID whose interface has the protocol's usage page, in the
// order hidapi lists them. Empty (never an error) when there are none, no HID subsystem at all, or no
// usb module (hidapi lives there: usb_backend.hpp).
std::vector<HidDeviceInfo> enumerate_hid(const HidId& id = {});

// The first device enumerate_hid(id) lists, or the one at a /dev/hidrawN path. Throws TransportError:
// "no HID device 1209:0001 found", "permission denied on /dev/hidrawN: install the udev rule
// (hmp flash --install-udev-rule)", "USB HID needs the usb module, which is not available (…)", …
std::unique_ptr<Transport> open_hid(const HidId& id = {});
// A path that exists but is not a hidraw node (a file, a folder, another device): BadInput.
std::unique_ptr<Transport> open_hid_path(const std::string& path);

}  // namespace hmp::transport
