#include "host/transport/device_spec.hpp"

#include <charconv>
#include <filesystem>
#include <system_error>

#include "host/common/error.hpp"
#include "host/transport/serial_transport.hpp"
#include "host/transport/sim_transport.hpp"

namespace hmp::transport {

namespace {

[[noreturn]] void bad(std::string_view text, std::string_view why) {
  throw BadInput("bad --device '" + std::string(text) + "': " + std::string(why) +
                 " (expected auto, sim, qemu, qemu:net, hid, hid:VID:PID, hid:/dev/hidrawN or serial:PATH[@BAUD])");
}

// "serial:/dev/ttyACM0@921600": the speed is the part after the last '@' when it is all digits, so a
// path that happens to contain '@' still works.
void split_baud(std::string_view text, DeviceSpec& spec, std::string_view whole) {
  const auto at = text.rfind('@');
  if (at != std::string_view::npos && at + 1 < text.size()) {
    const std::string_view digits = text.substr(at + 1);
    unsigned baud = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), baud);
    if (ec == std::errc{} && end == digits.data() + digits.size()) {
      if (baud == 0) bad(whole, "serial speed 0");
      spec.baud = baud;
      text = text.substr(0, at);
    }
  }
  if (text.empty()) bad(whole, "serial needs a path");
  spec.path = std::string(text);
}

}  // namespace

DeviceSpec parse_device_spec(std::string_view text) {
  DeviceSpec spec;
  if (text == "auto") return spec;
  if (text == "sim") {
    spec.kind = DeviceSpec::Kind::sim;
  } else if (text == "qemu" || text == "qemu:net") {
    spec.kind = DeviceSpec::Kind::qemu;
    spec.qemu_net = text == "qemu:net";
  } else if (text == "hid") {
    spec.kind = DeviceSpec::Kind::hid;
  } else if (text.starts_with("hid:")) {
    spec.kind = DeviceSpec::Kind::hid;
    const std::string_view rest = text.substr(4);
    if (rest.starts_with("/")) {
      spec.path = std::string(rest);
    } else {
      try {
        spec.hid = parse_hid_id(rest);
      } catch (const BadInput&) {
        bad(text, "VID:PID must be two hex numbers");
      }
    }
  } else if (text.starts_with("serial:")) {
    spec.kind = DeviceSpec::Kind::serial;
    split_baud(text.substr(7), spec, text);
  } else {
    bad(text, "unknown device kind");
  }
  return spec;
}

std::string to_string(const DeviceSpec& spec) {
  switch (spec.kind) {
    case DeviceSpec::Kind::automatic: return "auto";
    case DeviceSpec::Kind::sim: return "sim";
    case DeviceSpec::Kind::qemu: return spec.qemu_net ? "qemu:net" : "qemu";
    case DeviceSpec::Kind::hid: return "hid:" + (spec.path.empty() ? to_string(spec.hid) : spec.path);
    case DeviceSpec::Kind::serial:
      return "serial:" + spec.path + (spec.baud != 0 ? "@" + std::to_string(spec.baud) : "");
  }
  return "?";
}

namespace {

// VID:PID and serial of the HID device behind `link`, as enumerated now.
UsbIdentity usb_identity(const Transport& link, const HidId& id) {
  for (const HidDeviceInfo& d : enumerate_hid(id)) {
    if (link.name() == "hid:" + d.path) return {d.id, d.serial};
  }
  return {id, std::nullopt};
}

OpenedDevice open_kind(const DeviceSpec& spec, std::uint32_t tick_hz) {
  OpenedDevice opened;
  SimTransport::Options sim;
  sim.tick_hz = tick_hz;
  switch (spec.kind) {
    case DeviceSpec::Kind::automatic: {
      const std::vector<HidDeviceInfo> found = enumerate_hid(spec.hid);
      if (!found.empty()) {
        opened.transport = open_hid_path(found.front().path);
      } else {
        opened.transport = std::make_unique<SimTransport>(sim);
        opened.note = "no HID device " + to_string(spec.hid) + " found: using the simulated device";
      }
      break;
    }
    case DeviceSpec::Kind::sim: opened.transport = std::make_unique<SimTransport>(sim); break;
    case DeviceSpec::Kind::hid:
      opened.transport = spec.path.empty() ? open_hid(spec.hid) : open_hid_path(spec.path);
      break;
    case DeviceSpec::Kind::serial: {
      SerialTransport::Options options;
      options.baud = spec.baud;
      opened.transport = SerialTransport::open(spec.path, options);
      break;
    }
    case DeviceSpec::Kind::qemu:
      opened.qemu = std::make_unique<QemuDevice>(QemuDevice::Options{tick_hz, spec.qemu_net});
      opened.transport = opened.qemu->connect();
      break;
  }
  return opened;
}

}  // namespace

OpenedDevice open_device(const DeviceSpec& spec, std::uint32_t tick_hz) {
  OpenedDevice opened = open_kind(spec, tick_hz);
  opened.spec = spec;
  opened.tick_hz = tick_hz;
  if (opened.transport->name().starts_with("hid:")) opened.usb = usb_identity(*opened.transport, spec.hid);
  return opened;
}

Transport* reopen_device(OpenedDevice& opened) {
  if (opened.usb) {
    // The same device, wherever it enumerates now (its /dev/hidrawN may be another).
    for (const HidDeviceInfo& d : enumerate_hid(opened.usb->id)) {
      if (opened.usb->serial && d.serial != *opened.usb->serial) continue;
      opened.transport = open_hid_path(d.path);
      return opened.transport.get();
    }
    return nullptr;
  }
  if (opened.spec.kind == DeviceSpec::Kind::serial) {
    std::error_code ec;
    if (!std::filesystem::exists(opened.spec.path, ec)) return nullptr;
  }
  // The emulator goes after its link; a fresh one starts before the next link.
  opened.transport.reset();
  opened.qemu.reset();
  OpenedDevice again = open_kind(opened.spec, opened.tick_hz);
  opened.qemu = std::move(again.qemu);
  opened.transport = std::move(again.transport);
  return opened.transport.get();
}

}  // namespace hmp::transport
