// The usb module's entry (hmp-usb.so): the UsbBackend over hidapi (hid_link) and libusb (probe_scan).
#include "host/modules/module_loader.hpp"
#include "host/transport/usb/hid_link.hpp"
#include "host/transport/usb/probe_scan.hpp"
#include "host/transport/usb_backend.hpp"

namespace hmp::transport {
namespace {

class HidapiBackend final : public UsbBackend {
 public:
  std::vector<HidDeviceInfo> enumerate_hid(const HidId& id, std::string& error) const override {
    try {
      return HidTransport::enumerate(id);
    } catch (const std::exception& e) {
      error = e.what();
      return {};
    }
  }
  std::unique_ptr<Transport> open_hid_path(const std::string& path, std::string& error) const override {
    try {
      return HidTransport::open_path(path);
    } catch (const std::exception& e) {
      error = e.what();
      return nullptr;
    }
  }
  ScanResult scan_usb() const override { return scan_with_libusb(); }
};

}  // namespace
}  // namespace hmp::transport

HMP_DEFINE_MODULE(hmp::transport::UsbBackend, hmp::transport::HidapiBackend)
