#pragma once
// `--device auto|sim|qemu|hid[:VID:PID|:PATH]|serial:PATH[@BAUD]` (design §3): parsing, and opening the
// transport each kind names.
#include <memory>
#include <string>
#include <string_view>

#include "host/transport/hid_transport.hpp"
#include "host/transport/transport.hpp"

namespace hmp::transport {

struct DeviceSpec {
  enum class Kind { automatic, sim, qemu, hid, serial };
  Kind kind = Kind::automatic;
  HidId hid;          // hid: which VID:PID (default: the protocol's)
  std::string path;   // hid: a /dev/hidrawN given instead of an id; serial: the tty, pty or socket
  unsigned baud = 0;  // serial: line speed after '@' (0: keep the line's speed)
};

// Throws hmp::BadInput with a one-line message naming the text on anything else.
DeviceSpec parse_device_spec(std::string_view text);
std::string to_string(const DeviceSpec& spec);

struct OpenedDevice {
  std::unique_ptr<Transport> transport;
  std::string note;  // for the user when `auto` chose for them, e.g. "no HID device 1209:0001 found: using the simulated device"
};

// Opens sim (real-time pacing), hid and serial specs; `auto` takes the first HID device with the
// protocol's id and otherwise the simulated device (a HID device that is there but cannot be opened is
// an error, not a reason to fall back). `qemu` needs the emulator launcher: TransportError for now.
OpenedDevice open_device(const DeviceSpec& spec);

}  // namespace hmp::transport
