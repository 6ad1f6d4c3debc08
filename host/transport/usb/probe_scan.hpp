#pragma once
// The usb module's look at the USB bus through libusb, for the boards hidapi cannot see (flash/usb_scan.hpp).
#include "host/flash/usb_scan.hpp"

namespace hmp::flash {

ScanResult scan_with_libusb();

}  // namespace hmp::flash
