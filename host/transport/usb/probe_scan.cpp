// Finding an STM32 in DFU mode and ST-LINK probes with libusb; no USB access is an empty list and a reason.
#include "host/transport/usb/probe_scan.hpp"

#include <libusb.h>

#include <filesystem>

#include <fmt/format.h>

namespace hmp::transport {

namespace {
// Where Linux puts the USB device nodes libusb opens.
constexpr const char* kUsbDeviceNodes = "/dev/bus/usb";
}  // namespace

ScanResult scan_with_libusb() {
  ScanResult out;
  libusb_context* ctx = nullptr;
  if (const int rc = libusb_init(&ctx); rc != 0) {
    out.unavailable = fmt::format("libusb: {}", libusb_strerror(static_cast<libusb_error>(rc)));
    return out;
  }
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(ctx, &list);
  if (n < 0) {
    out.unavailable = fmt::format("libusb: {}", libusb_strerror(static_cast<libusb_error>(n)));
  } else if (n == 0 && !std::filesystem::exists(kUsbDeviceNodes)) {
    // libusb starts and lists nothing where the system gives no USB device nodes (a container): an empty
    // list would read as "nothing plugged in".
    out.unavailable = fmt::format("no {}: USB is not visible here (a container?)", kUsbDeviceNodes);
  }
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor d{};
    if (libusb_get_device_descriptor(list[i], &d) != 0) continue;
    if (const UsbId* id = known_id(d.idVendor, d.idProduct)) {
      out.found.push_back({id->kind, id->name, libusb_get_bus_number(list[i]), libusb_get_device_address(list[i])});
    }
  }
  if (list != nullptr) libusb_free_device_list(list, 1);
  libusb_exit(ctx);
  return out;
}

}  // namespace hmp::transport
