// Our HID device's ids, and the entry points that open it through the usb module (usb_backend.hpp).
#include "host/transport/hid_transport.hpp"

#include <charconv>
#include <cstdio>

#include "host/common/error.hpp"
#include "host/modules/module_loader.hpp"
#include "host/transport/usb_backend.hpp"

namespace hmp::transport {

namespace {

std::uint16_t parse_hex16(std::string_view text, std::string_view whole) {
  if (text.starts_with("0x") || text.starts_with("0X")) text.remove_prefix(2);
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value, 16);
  if (text.empty() || text.size() > 4 || ec != std::errc{} || end != text.data() + text.size()) {
    throw BadInput("bad USB id '" + std::string(whole) + "': expected VID:PID in hex, e.g. 1209:0001");
  }
  return static_cast<std::uint16_t>(value);
}

const UsbBackend& backend_or_throw() {
  std::string why;
  const UsbBackend* backend = usb_backend(&why);
  if (backend == nullptr) throw TransportError("USB HID needs the usb module, which is not available (" + why + ")");
  return *backend;
}

}  // namespace

std::string to_string(const HidId& id) {
  char buf[16];
  std::snprintf(buf, sizeof(buf), "%04x:%04x", id.vid, id.pid);
  return buf;
}

HidId parse_hid_id(std::string_view text) {
  const auto colon = text.find(':');
  if (colon == std::string_view::npos) {
    throw BadInput("bad USB id '" + std::string(text) + "': expected VID:PID in hex, e.g. 1209:0001");
  }
  return {parse_hex16(text.substr(0, colon), text), parse_hex16(text.substr(colon + 1), text)};
}

std::vector<HidDeviceInfo> enumerate_hid(const HidId& id) {
  const UsbBackend* backend = usb_backend();
  if (backend == nullptr) return {};
  std::string error;  // hidapi could not look: as good as no device
  return backend->enumerate_hid(id, error);
}

std::unique_ptr<Transport> open_hid(const HidId& id) {
  const std::vector<HidDeviceInfo> found = enumerate_hid(id);
  if (found.empty()) throw TransportError("no HID device " + to_string(id) + " found");
  return open_hid_path(found.front().path);
}

std::unique_ptr<Transport> open_hid_path(const std::string& path) {
  std::string error;
  std::unique_ptr<Transport> link = backend_or_throw().open_hid_path(path, error);
  if (!link) throw TransportError(error);
  return link;
}

const UsbBackend* usb_backend(std::string* why) { return modules::backend<UsbBackend>(why); }

}  // namespace hmp::transport
