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

#include "host/transport/link_state.hpp"
#include "host/transport/transport.hpp"

struct hid_device_;

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
// order hidapi lists them. Empty (never an error) when there are none or no HID subsystem at all.
std::vector<HidDeviceInfo> enumerate_hid(const HidId& id = {});

class HidTransport final : public Transport {
 public:
  // The first device enumerate_hid(id) lists. Throws TransportError: "no HID device 1209:0001 found",
  // "permission denied on /dev/hidrawN: install the udev rule (docs/host.md)", …
  static std::unique_ptr<HidTransport> open(const HidId& id = {});
  static std::unique_ptr<HidTransport> open_path(const std::string& path);
  ~HidTransport() override;

  bool send(const Report& report) override;
  Received receive(Report& out, Timeout timeout) override;
  std::string name() const override { return "hid:" + path_; }
  void close() override;
  bool is_open() const override { return state_.is_open(); }
  std::string closed_reason() const override { return state_.reason(); }
  LinkCounters counters() const override { return state_.counters(); }

 private:
  HidTransport(hid_device_* device, std::string path);
  hid_device_* device_;
  std::string path_;
  LinkState state_;
};

}  // namespace hmp::transport
