#pragma once
// Saying hello to the device a `--device` option names, for the commands that play on a device (play,
// study, live). Opening it, and finding it again after a loss, is transport::open_device / reopen_device.
#include "host/player/device_link.hpp"
#include "host/transport/device_spec.hpp"

namespace hmp::cli {

// --device's help where `auto` is the default (play, live).
inline constexpr const char* kDeviceHelp =
    "auto (HID, else the simulated device), sim, qemu, qemu:net, hid[:VID:PID], serial:PATH";

// DeviceLink options for the opened device (an emulator gets longer to answer hello).
player::DeviceLink::Options link_options_for(const transport::OpenedDevice& opened);

// link.connect(), with a hint when an emulated board does not answer; prints the device line on stderr.
protocol::HelloReply connect_and_describe(player::DeviceLink& link, const transport::OpenedDevice& opened);

}  // namespace hmp::cli
