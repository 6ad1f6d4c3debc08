#pragma once
// The USB module's interface (module "usb", host/transport/usb/): hidapi for our HID device and libusb
// for the boards that are not (yet) one — a DFU bootloader, an ST-LINK. hid_transport.hpp and
// usb_scan.hpp (both in host/transport/) are what the rest of hmp calls; they come here, so a command that touches no
// device (info, render, sim with the simulated device) never loads those libraries. Errors come back as text.
#include <memory>
#include <string>
#include <vector>

#include "host/transport/usb_scan.hpp"
#include "host/transport/hid_transport.hpp"
#include "host/transport/transport.hpp"

namespace hmp::transport {

class UsbBackend {
 public:
  static constexpr const char* kModule = "usb";
  static constexpr int kAbi = 1;

  // Our HID devices with this VID:PID (interfaces with the protocol's usage page). Empty `error`: the list
  // is complete (possibly empty); else hidapi could not look.
  virtual std::vector<HidDeviceInfo> enumerate_hid(const HidId& id, std::string& error) const = 0;
  // The device at a /dev/hidrawN path, or null and `error` says why (permissions name the udev rule).
  virtual std::unique_ptr<Transport> open_hid_path(const std::string& path, std::string& error) const = 0;
  virtual ScanResult scan_usb() const = 0;

 protected:
  ~UsbBackend() = default;  // one static object in the module, never deleted through this
};

// The USB module, loaded on first use; null (and `why`) when it cannot be had.
const UsbBackend* usb_backend(std::string* why = nullptr);

}  // namespace hmp::transport
