#pragma once
// Opening the device a `--device` option names and saying hello to it, for the commands that play on a
// device (play, study).
#include <cstdint>
#include <memory>
#include <string>

#include "host/player/device_link.hpp"
#include "host/player/qemu_device.hpp"
#include "host/transport/transport.hpp"

namespace hmp::cli {

struct OpenedLink {
  std::unique_ptr<player::QemuDevice> qemu;  // the emulator behind a `--device qemu` link (outlives the link)
  std::unique_ptr<transport::Transport> transport;
  std::string note;
};

OpenedLink open_link(const std::string& text, std::uint32_t tick_hz);

// DeviceLink options for the opened device (an emulator gets longer to answer hello).
player::DeviceLink::Options link_options_for(const OpenedLink& opened);

// link.connect(), with a hint when an emulated board does not answer; prints the device line on stderr.
protocol::HelloReply connect_and_describe(player::DeviceLink& link, const OpenedLink& opened);

}  // namespace hmp::cli
