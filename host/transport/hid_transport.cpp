// Our HID device's ids, and the entry points that open it through the usb module (usb_backend.hpp).
#include "host/transport/hid_transport.hpp"

#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <system_error>

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

// Throws BadInput when `path` exists but is not a hidraw device node: hidapi's hidraw backend does not
// check, and crashes on a regular file or another device (Debian 12's libhidapi-hidraw0 0.13). The kernel
// names a character device's subsystem under /sys/dev/char. A path that cannot be opened is left to the
// backend, which says why (a missing udev rule, for one) without opening it.
void check_hidraw_node(const std::string& path) {
  struct stat st {};
  if (::access(path.c_str(), R_OK | W_OK) != 0 || ::stat(path.c_str(), &st) != 0) return;
  const char* const kWhat = " (a /dev/hidrawN node: hmp devices lists them)";
  if (!S_ISCHR(st.st_mode)) {
    throw BadInput("HID device " + path + ": " + (S_ISDIR(st.st_mode) ? "a folder" : "not a device node") + kWhat);
  }
  const std::string sys =
      "/sys/dev/char/" + std::to_string(major(st.st_rdev)) + ":" + std::to_string(minor(st.st_rdev));
  std::error_code ec;
  const std::filesystem::path subsystem = std::filesystem::read_symlink(sys + "/subsystem", ec);
  if (ec || subsystem.filename() != "hidraw") throw BadInput("HID device " + path + ": not a hidraw node" + kWhat);
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
  check_hidraw_node(path);
  std::string error;
  std::unique_ptr<Transport> link = backend_or_throw().open_hid_path(path, error);
  if (!link) throw TransportError(error);
  return link;
}

const UsbBackend* usb_backend(std::string* why) { return modules::backend<UsbBackend>(why); }

}  // namespace hmp::transport
