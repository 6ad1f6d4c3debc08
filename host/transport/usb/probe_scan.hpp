#pragma once
// The usb module's look at the USB bus through libusb, for the boards hidapi cannot see (host/transport/usb_scan.hpp).
#include "host/transport/usb_scan.hpp"

namespace hmp::transport {

ScanResult scan_with_libusb();

}  // namespace hmp::transport
