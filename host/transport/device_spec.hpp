#pragma once
// `--device auto|sim|qemu[:net]|hid[:VID:PID|:PATH]|serial:PATH[@BAUD]` (design §3): parsing, and opening the
// transport each kind names.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "host/transport/hid_transport.hpp"
#include "host/transport/qemu_device.hpp"
#include "host/transport/transport.hpp"
#include "shared/synth/tick_rate.hpp"

namespace hmp::transport {

struct DeviceSpec {
  enum class Kind { automatic, sim, qemu, hid, serial };
  Kind kind = Kind::automatic;
  HidId hid;              // hid: which VID:PID (default: the protocol's)
  std::string path;       // hid: a /dev/hidrawN given instead of an id; serial: the tty, pty or socket
  unsigned baud = 0;      // serial: line speed after '@' (0: keep the line's speed)
  bool qemu_net = false;  // qemu: over the board's Ethernet controller instead of its UART
};

// Throws hmp::BadInput with a one-line message naming the text on anything else.
DeviceSpec parse_device_spec(std::string_view text);
std::string to_string(const DeviceSpec& spec);

// What tells a USB HID device from others, to find it again wherever it enumerates next.
struct UsbIdentity {
  HidId id;
  std::optional<std::string> serial;  // unknown (opened by a path that enumerates otherwise): any with the id
};

struct OpenedDevice {
  std::unique_ptr<QemuDevice> qemu;  // the emulator behind a `qemu` link (outlives the link)
  std::unique_ptr<Transport> transport;
  std::string note;  // for the user when `auto` chose for them, e.g. "no HID device 1209:0001 found: using the
                     // simulated device"
  // What finds the same device again (reopen_device).
  DeviceSpec spec;
  std::uint32_t tick_hz = 0;
  std::optional<UsbIdentity> usb;  // a USB HID device
};

// Opens every kind: sim (real-time pacing, at `tick_hz`), qemu (boots the emulated board at `tick_hz`),
// hid and serial; `auto` takes the first HID device with the protocol's id and otherwise the simulated
// device (a HID device that is there but cannot be opened is an error, not a reason to fall back).
// Throws TransportError with a one-line message.
OpenedDevice open_device(const DeviceSpec& spec, std::uint32_t tick_hz = synth::kNominalTickHz);

// The device `opened` had, opened again after it was lost: the USB device with the same VID:PID and serial
// wherever it enumerates now, the same serial path, a fresh simulated device, the emulator started again.
// Null while it is not there; throws TransportError when it is there but cannot be opened. The old
// transport is replaced (whoever reads it must have stopped).
Transport* reopen_device(OpenedDevice& opened);

}  // namespace hmp::transport
