// hmp devices [--json] [--id VID:PID] [--timeout-ms MS] — the connected HID devices and what each says
// about itself when greeted (design §3): protocol and firmware version, board, tick rate, state.
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "host/cli/commands.hpp"
#include "host/cli/run_command.hpp"
#include "host/common/error.hpp"
#include "host/common/install_layout.hpp"
#include "host/transport/usb_scan.hpp"
#include "host/transport/handshake.hpp"
#include "host/transport/hid_transport.hpp"
#include "host/transport/usb_backend.hpp"

namespace hmp::cli {

namespace {

struct DevicesOptions {
  bool json = false;
  std::string id = transport::to_string(transport::HidId{});
  int timeout_ms = 500;
};

struct Probe {
  transport::HidDeviceInfo info;
  std::optional<transport::DeviceIdentity> identity;
  std::string error;  // why there is no identity
};

Probe probe(const transport::HidDeviceInfo& info, int timeout_ms) {
  Probe p{info, std::nullopt, ""};
  try {
    auto link = transport::open_hid_path(info.path);
    p.identity = transport::say_hello(*link, 1, std::chrono::milliseconds(timeout_ms));
    if (!p.identity) {
      p.error = link->is_open() ? fmt::format("no reply to Hello within {} ms", timeout_ms) : link->closed_reason();
    }
  } catch (const transport::TransportError& e) {
    p.error = e.what();
  }
  return p;
}

nlohmann::json to_json(const Probe& p) {
  const transport::HidDeviceInfo& d = p.info;
  nlohmann::json j = {{"path", d.path},
                      {"vid", fmt::format("{:04x}", d.id.vid)},
                      {"pid", fmt::format("{:04x}", d.id.pid)},
                      {"serial", d.serial},
                      {"manufacturer", d.manufacturer},
                      {"product", d.product},
                      {"release", fmt::format("{:x}.{:02x}", d.release >> 8, d.release & 0xFF)},
                      {"interface", d.interface_number}};
  if (!p.identity) {
    j["error"] = p.error;
    return j;
  }
  const protocol::HelloReply& h = p.identity->hello;
  j["protocol_version"] = h.protocol_version;
  j["compatible"] = p.identity->compatible();
  if (!p.identity->compatible()) return j;
  j["firmware"] = transport::firmware_version(h);
  j["board"] = transport::board_name(h.board);
  j["tick_hz"] = h.tick_hz;
  j["voices"] = h.voices;
  j["queue_capacity"] = h.queue_capacity;
  j["preset_slots"] = h.preset_slots;
  j["board_flags"] = transport::board_flag_names(h.board_flags);
  if (const auto& s = p.identity->status) {
    j["status"] = {{"state", transport::state_name(s->state)},
                   {"tick", s->tick},
                   {"faults", transport::fault_names(s->faults)},
                   {"queue_free", s->queue_free},
                   {"late", s->late},
                   {"stolen", s->stolen},
                   {"rejected", s->rejected},
                   {"started", s->started}};
  }
  return j;
}

void print_text(const Probe& p) {
  const transport::HidDeviceInfo& d = p.info;
  std::string who = d.manufacturer;
  if (!d.product.empty()) who += (who.empty() ? "" : " ") + d.product;
  fmt::print("{}  {}  serial {}{}\n", transport::to_string(d.id), d.path, d.serial.empty() ? "-" : d.serial,
             who.empty() ? "" : "  \"" + who + "\"");
  if (!p.identity) {
    fmt::print("  {}\n", p.error);
    return;
  }
  const protocol::HelloReply& h = p.identity->hello;
  if (!p.identity->compatible()) {
    fmt::print("  incompatible: protocol {} (this hmp speaks {})\n", h.protocol_version, protocol::kProtocolVersion);
    return;
  }
  fmt::print("  protocol {}, firmware {}, board {}, {} Hz, {} voices, queue {} reports\n", h.protocol_version,
             transport::firmware_version(h), transport::board_name(h.board), h.tick_hz, h.voices, h.queue_capacity);
  if (h.board_flags != 0) fmt::print("  board: {}\n", transport::board_flag_names(h.board_flags));
  if (transport::firmware_version(h) != install::version_text()) {
    // The protocol matches, so it plays; but a firmware of another release may differ in what it does.
    fmt::print("  warning: firmware {} differs from this hmp's {}: `hmp flash` writes the matching one\n",
               transport::firmware_version(h), install::version_text());
  }
  if (const auto& s = p.identity->status) {
    fmt::print("  state {}, faults {}, tick {}\n", transport::state_name(s->state), transport::fault_names(s->faults),
               s->tick);
  } else {
    fmt::print("  state unknown (no Status after the HelloReply)\n");
  }
}

int run_devices(const DevicesOptions& o) {
  const transport::HidId id = transport::parse_hid_id(o.id);
  if (o.timeout_ms < 1 || o.timeout_ms > 60'000) throw BadInput("--timeout-ms: must be in [1, 60000]");
  // Without the usb module (hidapi, libusb) nothing can be found: say so rather than report no device.
  if (std::string why; transport::usb_backend(&why) == nullptr) {
    std::fprintf(stderr, "warning: cannot look for USB devices: the usb module is not available (%s)\n", why.c_str());
  }
  std::vector<Probe> probes;
  for (const transport::HidDeviceInfo& info : transport::enumerate_hid(id)) probes.push_back(probe(info, o.timeout_ms));

  // Boards that are not our HID device yet: an STM32 in its DFU bootloader, an ST-LINK probe (libusb).
  const transport::ScanResult usb = transport::scan_usb();

  if (o.json) {
    nlohmann::json list = nlohmann::json::array();
    for (const Probe& p : probes) list.push_back(to_json(p));
    nlohmann::json flashable = nlohmann::json::array();
    for (const transport::FoundProbe& f : usb.found) {
      flashable.push_back({{"kind", f.kind == transport::ProbeKind::stm32_dfu ? "stm32_dfu" : "stlink"},
                           {"name", f.name},
                           {"bus", f.bus},
                           {"address", f.address}});
    }
    nlohmann::json out{{"id", transport::to_string(id)}, {"devices", list}, {"flashable", flashable}};
    if (!usb.unavailable.empty()) out["usb_scan_error"] = usb.unavailable;
    std::printf("%s\n", out.dump().c_str());
    return kExitOk;
  }
  for (const transport::FoundProbe& f : usb.found) fmt::print("{}\n", transport::describe(f));
  if (probes.empty()) {
    fmt::print("no HID device {} found (the simulated device needs none: hmp play --device sim)\n",
               transport::to_string(id));
    if (!usb.unavailable.empty()) fmt::print("boards to flash cannot be looked for: {}\n", usb.unavailable);
    return kExitOk;
  }
  for (const Probe& p : probes) print_text(p);
  return kExitOk;
}

}  // namespace

int print_hid_devices(int timeout_ms) {
  int n = 0;
  for (const transport::HidDeviceInfo& info : transport::enumerate_hid(transport::HidId{})) {
    print_text(probe(info, timeout_ms));
    ++n;
  }
  return n;
}

void register_devices(CLI::App& app, Registry& registry) {
  auto opts = std::make_shared<DevicesOptions>();
  CLI::App* cmd = app.add_subcommand("devices", "List connected devices (USB HID) with firmware version and state");
  cmd->add_flag("--json", opts->json, "Print one JSON object");
  cmd->add_option("--id", opts->id, "USB VID:PID to look for (hex)")->capture_default_str();
  cmd->add_option("--timeout-ms", opts->timeout_ms, "How long to wait for each device's reply")->capture_default_str();
  cmd->callback([opts, &registry] { registry.set([opts] { return run_devices(*opts); }); });
}

}  // namespace hmp::cli
