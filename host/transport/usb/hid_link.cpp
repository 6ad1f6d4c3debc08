// The usb module's HID link: our device through hidapi's hidraw backend (hid_transport.hpp says what it
// carries). Nothing here throws out of the module: failures come back as text (usb_module.cpp).
#include "host/transport/usb/hid_link.hpp"

#include <hidapi.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <mutex>

#include "host/common/error.hpp"

namespace hmp::transport {

namespace {

using SteadyClock = std::chrono::steady_clock;

// receive() waits in slices this long so that close() from another thread is noticed promptly
// (hid_read_timeout cannot be interrupted, and the device must not be freed under it).
constexpr int kReadSliceMs = 20;

void init_hidapi() {
  static std::once_flag once;
  static bool ok = false;
  std::call_once(once, [] { ok = hid_init() == 0; });
  if (!ok) throw TransportError("cannot initialise hidapi (hidraw backend)");  // caught in usb_module.cpp
}

// hidapi's strings are wchar_t (UTF-32 on Linux); the rest of the program speaks UTF-8.
std::string utf8(const wchar_t* text) {
  std::string out;
  if (text == nullptr) return out;
  for (; *text != 0; ++text) {
    auto c = static_cast<std::uint32_t>(*text);
    if (c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF)) c = 0xFFFD;
    if (c < 0x80) {
      out += static_cast<char>(c);
    } else if (c < 0x800) {
      out += static_cast<char>(0xC0 | (c >> 6));
      out += static_cast<char>(0x80 | (c & 0x3F));
    } else if (c < 0x10000) {
      out += static_cast<char>(0xE0 | (c >> 12));
      out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (c & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (c >> 18));
      out += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (c & 0x3F));
    }
  }
  return out;
}

}  // namespace

std::vector<HidDeviceInfo> HidTransport::enumerate(const HidId& id) {
  init_hidapi();
  std::vector<HidDeviceInfo> out;
  hid_device_info* list = hid_enumerate(id.vid, id.pid);
  for (const hid_device_info* d = list; d != nullptr; d = d->next) {
    if (d->usage_page != protocol::kUsagePage) continue;  // another interface of a composite device
    HidDeviceInfo info;
    info.path = d->path != nullptr ? d->path : "";
    info.id = {d->vendor_id, d->product_id};
    info.release = d->release_number;
    info.serial = utf8(d->serial_number);
    info.manufacturer = utf8(d->manufacturer_string);
    info.product = utf8(d->product_string);
    info.usage_page = d->usage_page;
    info.usage = d->usage;
    info.interface_number = d->interface_number;
    out.push_back(std::move(info));
  }
  hid_free_enumeration(list);
  return out;
}

std::unique_ptr<HidTransport> HidTransport::open_path(const std::string& path) {
  init_hidapi();
  // hidapi only says "failed"; the node's permissions tell the user what to do about it.
  if (::access(path.c_str(), R_OK | W_OK) != 0) {
    const int err = errno;
    if (err == EACCES || err == EPERM) {
      throw TransportError("permission denied on " + path + ": install the udev rule (hmp flash --install-udev-rule)");
    }
    throw TransportError("cannot open HID device " + path + ": " + std::strerror(err));
  }
  hid_device* device = hid_open_path(path.c_str());
  if (device == nullptr) {
    const std::string why = utf8(hid_error(nullptr));
    throw TransportError("cannot open HID device " + path + (why.empty() ? "" : ": " + why));
  }
  return std::unique_ptr<HidTransport>(new HidTransport(device, path));
}

HidTransport::HidTransport(hid_device* device, std::string path) : device_(device), path_(std::move(path)) {}

HidTransport::~HidTransport() {
  close();
  hid_close(device_);
}

void HidTransport::close() { state_.mark_closed("closed by the host"); }

bool HidTransport::send(const Report& report) {
  if (!state_.is_open()) return false;
  // Unnumbered reports: hidapi wants a leading report ID 0, which is not sent on the wire.
  unsigned char buf[1 + protocol::kReportSize];
  buf[0] = 0;
  std::memcpy(buf + 1, report, protocol::kReportSize);
  if (hid_write(device_, buf, sizeof(buf)) < 0) {
    const std::string why = utf8(hid_error(device_));
    state_.mark_closed("HID write to " + path_ + " failed" + (why.empty() ? "" : ": " + why));
    return false;
  }
  state_.count_sent();
  return true;
}

Received HidTransport::receive(Report& out, Timeout timeout) {
  const auto deadline = SteadyClock::now() + timeout;
  unsigned char buf[protocol::kReportSize + 1];
  for (;;) {
    if (!state_.is_open()) return Received::closed;
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - SteadyClock::now()).count();
    const int slice = static_cast<int>(std::clamp<long long>(left, 0, kReadSliceMs));
    // One byte more than a report: a longer one (a misbehaving device) is then seen and dropped.
    const int n = hid_read_timeout(device_, buf, sizeof(buf), slice);
    if (n < 0) {
      const std::string why = utf8(hid_error(device_));
      state_.mark_closed("HID device " + path_ + " gone" + (why.empty() ? "" : ": " + why));
      return Received::closed;
    }
    if (n == static_cast<int>(protocol::kReportSize)) {
      std::memcpy(out, buf, protocol::kReportSize);
      state_.count_received();
      return Received::report;
    }
    if (n > 0) state_.count_dropped();
    if (left <= kReadSliceMs && SteadyClock::now() >= deadline) return Received::timeout;
  }
}

}  // namespace hmp::transport
