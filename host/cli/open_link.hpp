#pragma once
// Opening the device a `--device` option names and saying hello to it, for the commands that play on a
// device (play, study).
#include <cstdint>
#include <memory>
#include <string>

#include <optional>

#include "host/player/device_link.hpp"
#include "host/player/qemu_device.hpp"
#include "host/transport/device_spec.hpp"
#include "host/transport/transport.hpp"

namespace hmp::cli {

struct OpenedLink {
  std::unique_ptr<player::QemuDevice> qemu;  // the emulator behind a `--device qemu` link (outlives the link)
  std::unique_ptr<transport::Transport> transport;
  std::string note;
  // What finds the same device again (reopen_link).
  transport::DeviceSpec spec;
  std::uint32_t tick_hz = 0;
  struct UsbIdentity {
    transport::HidId id;
    std::optional<std::string> serial;  // unknown: any device with the id
  };
  std::optional<UsbIdentity> usb;  // a USB HID device
};

OpenedLink open_link(const std::string& text, std::uint32_t tick_hz);

// The device `opened` had, opened again after it was lost: the USB device with the same VID:PID and
// serial wherever it enumerates now, the same serial path, a fresh simulated device, the emulator
// started again. Null while it is not there; throws transport::TransportError when it is there but
// cannot be opened. The old transport is replaced (the caller's DeviceLink must be detached).
transport::Transport* reopen_link(OpenedLink& opened);

// DeviceLink options for the opened device (an emulator gets longer to answer hello).
player::DeviceLink::Options link_options_for(const OpenedLink& opened);

// link.connect(), with a hint when an emulated board does not answer; prints the device line on stderr.
protocol::HelloReply connect_and_describe(player::DeviceLink& link, const OpenedLink& opened);

}  // namespace hmp::cli
