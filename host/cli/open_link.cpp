#include "host/cli/open_link.hpp"

#include <cstdio>

#include <fmt/format.h>

#include "host/transport/device_spec.hpp"
#include "host/transport/handshake.hpp"
#include "host/transport/sim_transport.hpp"

namespace hmp::cli {

OpenedLink open_link(const std::string& text, std::uint32_t tick_hz) {
  const transport::DeviceSpec spec = transport::parse_device_spec(text);
  OpenedLink out;
  transport::SimTransport::Options sim;
  sim.tick_hz = tick_hz;
  switch (spec.kind) {
    case transport::DeviceSpec::Kind::sim:
      out.transport = std::make_unique<transport::SimTransport>(sim);
      return out;
    case transport::DeviceSpec::Kind::qemu:
      out.qemu = std::make_unique<player::QemuDevice>(player::QemuDevice::Options{tick_hz});
      out.transport = out.qemu->connect();
      return out;
    case transport::DeviceSpec::Kind::automatic: {
      transport::OpenedDevice opened = transport::open_device(spec);
      out.note = opened.note;
      // The fallback simulated device runs at the tick rate asked for.
      if (!opened.note.empty()) opened.transport = std::make_unique<transport::SimTransport>(sim);
      out.transport = std::move(opened.transport);
      return out;
    }
    default:
      out.transport = transport::open_device(spec).transport;
      return out;
  }
}

player::DeviceLink::Options link_options_for(const OpenedLink& opened) {
  player::DeviceLink::Options options;
  // An emulator boots first, and on a busy host that can take a while.
  if (opened.qemu) options.hello_timeout = std::chrono::milliseconds(3000);
  return options;
}

protocol::HelloReply connect_and_describe(player::DeviceLink& link, const OpenedLink& opened) {
  protocol::HelloReply hello;
  try {
    hello = link.connect();
  } catch (const player::LinkError& e) {
    // An emulated board that does not answer is most likely an image of something else.
    if (!opened.qemu) throw;
    throw player::LinkError(fmt::format("{} (image {}: is it the qemu-an386 firmware?)", e.what(), opened.qemu->image()));
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
