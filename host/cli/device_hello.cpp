#include "host/cli/device_hello.hpp"

#include <cstdio>

#include <fmt/format.h>

#include "host/transport/handshake.hpp"

namespace hmp::cli {

player::DeviceLink::Options link_options_for(const transport::OpenedDevice& opened) {
  player::DeviceLink::Options options;
  // An emulator boots first, and on a busy host that can take a while.
  if (opened.qemu) options.hello_timeout = std::chrono::milliseconds(3000);
  return options;
}

protocol::HelloReply connect_and_describe(player::DeviceLink& link, const transport::OpenedDevice& opened) {
  protocol::HelloReply hello;
  try {
    hello = link.connect();
  } catch (const player::LinkError& e) {
    // An emulated board that does not answer is most likely an image of something else.
    if (!opened.qemu) throw;
    throw player::LinkError(
        fmt::format("{} (image {}: is it the qemu-an386 firmware?)", e.what(), opened.qemu->image()));
  }
  std::fprintf(stderr, "device %s: board %s, firmware %s, %u Hz, %u voices\n", opened.transport->name().c_str(),
               transport::board_name(hello.board), transport::firmware_version(hello).c_str(), hello.tick_hz,
               static_cast<unsigned>(hello.voices));
  if (hello.board_flags != 0) {
    std::fprintf(stderr, "device %s: board condition %s (docs/boards.md)\n", opened.transport->name().c_str(),
                 transport::board_flag_names(hello.board_flags).c_str());
  }
  return hello;
}

}  // namespace hmp::cli
