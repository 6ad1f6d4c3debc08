#include "host/transport/device_spec.hpp"

#include <charconv>

#include "host/common/error.hpp"
#include "host/transport/serial_transport.hpp"
#include "host/transport/sim_transport.hpp"

namespace hmp::transport {

namespace {

[[noreturn]] void bad(std::string_view text, std::string_view why) {
  throw BadInput("bad --device '" + std::string(text) + "': " + std::string(why) +
                 " (expected auto, sim, qemu, hid, hid:VID:PID, hid:/dev/hidrawN or serial:PATH[@BAUD])");
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
  } else if (text == "qemu") {
    spec.kind = DeviceSpec::Kind::qemu;
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
    case DeviceSpec::Kind::qemu: return "qemu";
    case DeviceSpec::Kind::hid: return "hid:" + (spec.path.empty() ? to_string(spec.hid) : spec.path);
    case DeviceSpec::Kind::serial:
      return "serial:" + spec.path + (spec.baud != 0 ? "@" + std::to_string(spec.baud) : "");
  }
  return "?";
}

OpenedDevice open_device(const DeviceSpec& spec) {
  OpenedDevice opened;
  switch (spec.kind) {
    case DeviceSpec::Kind::automatic: {
      const std::vector<HidDeviceInfo> found = enumerate_hid(spec.hid);
      if (!found.empty()) {
        opened.transport = open_hid_path(found.front().path);
      } else {
        opened.transport = std::make_unique<SimTransport>();
        opened.note = "no HID device " + to_string(spec.hid) + " found: using the simulated device";
      }
      break;
    }
    case DeviceSpec::Kind::sim: opened.transport = std::make_unique<SimTransport>(); break;
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
      throw TransportError("--device qemu is not available yet (use serial:PATH with a running qemu-system-arm)");
  }
  return opened;
}

}  // namespace hmp::transport
