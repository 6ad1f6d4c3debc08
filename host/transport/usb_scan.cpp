// usb_scan: what the flasher looks for on the USB bus; the looking is done by the usb module (libusb).
#include "host/transport/usb_scan.hpp"

#include <fmt/format.h>

#include "host/transport/usb_backend.hpp"

namespace hmp::transport {

const UsbId* known_id(std::uint16_t vid, std::uint16_t pid) {
  for (const UsbId& id : kKnownIds) {
    if (id.vid == vid && id.pid == pid) return &id;
  }
  return nullptr;
}

ScanResult scan_usb() {
  std::string why;
  const UsbBackend* backend = usb_backend(&why);
  if (backend == nullptr) return {{}, "the usb module is not available (" + why + ")"};
  return backend->scan_usb();
}

std::string describe(const FoundProbe& p) {
  return fmt::format("{} on bus {} device {} — run hmp flash{}", p.name, p.bus, p.address,
                     p.kind == ProbeKind::stlink ? " --method stlink" : "");
}

}  // namespace hmp::transport
