#include "host/cli/open_link.hpp"

#include <cstdio>
#include <filesystem>

#include <fmt/format.h>

#include "host/transport/device_spec.hpp"
#include "host/transport/handshake.hpp"
#include "host/transport/sim_transport.hpp"

namespace hmp::cli {

namespace {

// What tells the HID device behind `link` from others: its VID:PID and serial, as enumerated now.
OpenedLink::UsbIdentity usb_identity(const transport::Transport& link, const transport::HidId& id) {
  for (const transport::HidDeviceInfo& d : transport::enumerate_hid(id)) {
    if (link.name() == "hid:" + d.path) return {d.id, d.serial};
  }
  return {id, std::nullopt};  // opened by a path that enumerates otherwise: its id at least
}

OpenedLink open_spec(const transport::DeviceSpec& spec, std::uint32_t tick_hz) {
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

}  // namespace

OpenedLink open_link(const std::string& text, std::uint32_t tick_hz) {
  const transport::DeviceSpec spec = transport::parse_device_spec(text);
  OpenedLink out = open_spec(spec, tick_hz);
  out.spec = spec;
  out.tick_hz = tick_hz;
  if (out.transport->name().starts_with("hid:")) out.usb = usb_identity(*out.transport, spec.hid);
  return out;
}

transport::Transport* reopen_link(OpenedLink& opened) {
  if (opened.usb) {
    // The same device, wherever it enumerates now (its /dev/hidrawN may be another).
    for (const transport::HidDeviceInfo& d : transport::enumerate_hid(opened.usb->id)) {
      if (opened.usb->serial && d.serial != *opened.usb->serial) continue;
      opened.transport = transport::open_hid_path(d.path);
      return opened.transport.get();
    }
    return nullptr;
  }
  if (opened.spec.kind == transport::DeviceSpec::Kind::serial) {
    std::error_code ec;
    if (!std::filesystem::exists(opened.spec.path, ec)) return nullptr;
  }
  // The emulator goes after its link; the fresh one is started before the next link.
  opened.transport.reset();
  opened.qemu.reset();
  OpenedLink again = open_spec(opened.spec, opened.tick_hz);
  opened.qemu = std::move(again.qemu);
  opened.transport = std::move(again.transport);
  return opened.transport.get();
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
