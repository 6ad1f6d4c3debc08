#pragma once
// host/transport/usb/: the usb module (hmp-usb.so): hidapi and libusb behind usb_backend.hpp.
// HidTransport is our device as a Transport: each interrupt transfer is one 64-byte report (no report
// IDs), so there is no framing.
#include <memory>
#include <string>
#include <vector>

#include "host/transport/hid_transport.hpp"
#include "host/transport/link_state.hpp"
#include "host/transport/transport.hpp"

struct hid_device_;

namespace hmp::transport {

class HidTransport final : public Transport {
 public:
  // Throw TransportError (the module's entry turns it into text).
  static std::vector<HidDeviceInfo> enumerate(const HidId& id);
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
