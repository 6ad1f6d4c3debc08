// boards/usb-sim: the firmware core and its USB device stack (firmware/usb), built natively, ticking in real
// time, presented as a USB device to QEMU through `-device usb-redir,chardev=…` on a unix socket. It plays
// usbredir's "usb-host" side with libusbredirparser: QEMU's xHCI, and the Linux guest behind it, see our
// descriptors and talk to our stack exactly as a host controller would (docs/usb.md, "Linux guest test").
//
// usage: hmp-usb-sim --socket PATH [--tick-hz N]
//   listens on PATH (a unix socket; QEMU connects with -chardev socket,path=PATH); one session.
//   SIGUSR1 pulls the device out (device_disconnect), SIGUSR2 plugs it back in; SIGTERM/SIGINT end it.
// The rig is the controller behind the stack's seam (firmware/usb/dcd.hpp): usbredir's control packets
// become a SETUP and the packets of its stages, interrupt packets become OUT completions, and the IN
// packets the stack queues go out as interrupt_packets while QEMU has interrupt receiving started.
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <deque>
#include <optional>
#include <string>
#include <vector>

extern "C" {
#include <usbredirparser.h>
}

#include "boards/usb-sim/control_transfer.hpp"
#include "firmware/core.hpp"
#include "firmware/usb/device.hpp"

namespace {

namespace usb = hmp::fw::usb;
namespace protocol = hmp::protocol;
using Clock = std::chrono::steady_clock;

volatile sig_atomic_t g_unplug = 0, g_replug = 0, g_stop = 0;

// The endpoint state the stack asked for (dcd.hpp), as a host controller keeps it; the packet (buffer, len,
// in_data) is meaningful while `armed`.
struct Endpoint : hmp::usb_host::Packet {
  bool open = false, stalled = false, armed = false;
  static Endpoint opened() {
    Endpoint e;
    e.open = true;
    return e;
  }
};

// The controller is also endpoint 0 as the shared control-transfer model reads it (usb_host::Ep0).
class UsbSim : private hmp::usb_host::Ep0 {
 public:
  UsbSim(int fd, std::uint32_t tick_hz) : fd_(fd), core_(seam(), tick_hz), device_(dcd(), core_, "USBSIM0001") {
    tick_period_ = std::chrono::nanoseconds(1'000'000'000LL / tick_hz);
    parser_ = usbredirparser_create();
    if (parser_ == nullptr) die("usbredirparser_create failed");
    wire_callbacks();
    std::uint32_t caps[USB_REDIR_CAPS_SIZE] = {};
    // QEMU's xHCI path needs these (hw/usb/redirect.c): max packet sizes in ep_info, 64-bit ids, 32-bit
    // bulk lengths, and the device version in device_connect.
    for (int cap : {usb_redir_cap_connect_device_version, usb_redir_cap_ep_info_max_packet_size,
                    usb_redir_cap_64bits_ids, usb_redir_cap_32bits_bulk_length}) {
      usbredirparser_caps_set_cap(caps, cap);
    }
    usbredirparser_init(parser_, "hmp-usb-sim 1", caps, USB_REDIR_CAPS_SIZE, usbredirparser_fl_usb_host);
  }
  ~UsbSim() override { usbredirparser_destroy(parser_); }

  int run() {
    auto next_tick = Clock::now();
    while (!g_stop) {
      if (g_unplug) {
        g_unplug = 0;
        unplug();
      }
      if (g_replug) {
        g_replug = 0;
        plug();
      }
      // Sleep until the next tick or until QEMU sends something, to the nanosecond: a millisecond timeout
      // would round the last part of every tick period down to zero and spin a core the guest needs.
      const auto wait = std::max<Clock::duration>(next_tick - Clock::now(), Clock::duration::zero());
      const auto wait_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(wait).count();
      const timespec timeout{static_cast<time_t>(wait_ns / 1'000'000'000), static_cast<long>(wait_ns % 1'000'000'000)};
      pollfd p{fd_, static_cast<short>(POLLIN | (usbredirparser_has_data_to_write(parser_) ? POLLOUT : 0)), 0};
      if (::ppoll(&p, 1, &timeout, nullptr) < 0 && errno != EINTR) die("poll failed");
      if (p.revents & (POLLIN | POLLHUP)) {
        if (usbredirparser_do_read(parser_) == usbredirparser_read_io_error) {
          std::fprintf(stderr, "usb-sim: QEMU closed the connection\n");
          return 0;
        }
      }
      // Ticks in real time; a late loop catches up (bounded: at most 50 ticks at once).
      for (int n = 0; Clock::now() >= next_tick && n < 50; ++n) {
        core_.on_tick();
        next_tick += tick_period_;
      }
      // The core drains its inbox between ticks, as the board's main loop does, so a held OUT report is
      // taken as soon as there is room rather than at the next tick.
      while (core_.poll()) {
      }
      device_.poll();
      if (Clock::now() >= next_tick) next_tick = Clock::now();
      pump();
      if (usbredirparser_has_data_to_write(parser_) &&
          usbredirparser_do_write(parser_) == usbredirparser_write_io_error) {
        std::fprintf(stderr, "usb-sim: write to QEMU failed\n");
        return 0;
      }
    }
    return 0;
  }

 private:
  [[noreturn]] static void die(const char* what) {
    std::fprintf(stderr, "usb-sim: %s\n", what);
    std::exit(1);
  }
  static UsbSim& self(void* p) { return *static_cast<UsbSim*>(p); }

  hmp::fw::BoardSeam seam() {
    hmp::fw::BoardSeam s;
    s.ctx = this;
    s.send = [](void* c, const protocol::Report& r) { return self(c).device_.queue_report(r); };
    s.log = [](void*, const char* line) { std::fprintf(stderr, "usb-sim: firmware: %s\n", line); };
    s.id = protocol::Board::sim;
    return s;
  }

  Endpoint& ep(std::uint8_t addr) { return eps_[addr & 0x0F][(addr & 0x80) ? 1 : 0]; }

  usb::Dcd dcd() {
    usb::Dcd d;
    d.ctx = this;
    d.connect = [](void*, bool) {};
    d.set_address = [](void*, std::uint8_t) {};  // QEMU owns the address (it never forwards SET_ADDRESS)
    d.ep_open = [](void* c, std::uint8_t a, usb::EpType, std::uint16_t) { self(c).ep(a) = Endpoint::opened(); };
    d.ep_close = [](void* c, std::uint8_t a) { self(c).ep(a) = Endpoint{}; };
    d.ep_stall = [](void* c, std::uint8_t a) {
      Endpoint& e = self(c).ep(a);
      e.stalled = true;
      if ((a & 0x0F) != 0) e.armed = false;
      if ((a & 0x0F) == 0) self(c).ep(a ^ 0x80).stalled = true;
    };
    d.ep_clear_stall = [](void* c, std::uint8_t a) {
      Endpoint& e = self(c).ep(a);
      e.stalled = false;
      e.armed = false;
    };
    d.ep_xfer = [](void* c, std::uint8_t a, std::uint8_t* buf, std::uint16_t len) {
      Endpoint& e = self(c).ep(a);
      if ((a & 0x0F) != 0 && !e.open) return false;
      e.armed = true;
      e.buffer = buf;
      e.len = len;
      if (a & 0x80) e.in_data.assign(buf, buf + len);
      return true;
    };
    return d;
  }

  // ---- the device appears and disappears ----

  void plug() {
    if (connected_ || !peer_hello_) return;
    for (auto& pair : eps_) pair[0] = pair[1] = Endpoint{};
    eps_[0][0].open = eps_[0][1].open = true;
    device_.on_bus_reset();
    control(0x00, 5, 1, 0, 0, nullptr);  // our own SET_ADDRESS: QEMU handles the guest's itself
    send_interface_and_ep_info();
    usb_redir_device_connect_header h{};
    h.speed = usb_redir_speed_full;
    h.vendor_id = protocol::kUsbVid;
    h.product_id = protocol::kUsbPid;
    h.device_version_bcd = 0x0100;
    usbredirparser_send_device_connect(parser_, &h);
    connected_ = true;
    std::fprintf(stderr, "usb-sim: device connected\n");
  }

  void unplug() {
    if (!connected_) return;
    usbredirparser_send_device_disconnect(parser_);
    connected_ = false;
    interrupt_receiving_ = false;
    held_out_.clear();
    device_.on_bus_reset();  // the outputs go safe as on a real unplug
    std::fprintf(stderr, "usb-sim: device disconnected\n");
  }

  void send_interface_and_ep_info() {
    usb_redir_interface_info_header ii{};
    ii.interface_count = device_.configuration() ? 1 : 0;
    ii.interface[0] = 0;
    ii.interface_class[0] = 0x03;
    usbredirparser_send_interface_info(parser_, &ii);
    usb_redir_ep_info_header ei{};
    for (int i = 0; i < 32; ++i) ei.type[i] = usb_redir_type_invalid;
    ei.type[0] = ei.type[16] = usb_redir_type_control;
    ei.max_packet_size[0] = ei.max_packet_size[16] = usb::kEp0Size;
    if (device_.configuration()) {
      // Index: endpoint number, + 16 for IN.
      ei.type[1] = ei.type[17] = usb_redir_type_interrupt;
      ei.interval[1] = ei.interval[17] = usb::kInterval;
      ei.max_packet_size[1] = ei.max_packet_size[17] = usb::kReportSize;
    }
    usbredirparser_send_ep_info(parser_, &ei);
  }

  // ---- control transfers: a SETUP and its stages, as a host controller runs them ----

  // Runs one through the shared model (control_transfer.hpp) and returns the usbredir status; IN data goes
  // to `in` (as much as came, also when the transfer failed part way).
  std::uint8_t control(std::uint8_t type, std::uint8_t req, std::uint16_t value, std::uint16_t index,
                       std::uint16_t length, const std::uint8_t* out_data, std::vector<std::uint8_t>* in = nullptr) {
    const usb::Setup setup{type, req, value, index, length};
    const hmp::usb_host::ControlResult r = hmp::usb_host::control_transfer(device_, *this, setup, out_data);
    if (in) in->insert(in->end(), r.data.begin(), r.data.end());
    switch (r.outcome) {
      case hmp::usb_host::ControlOutcome::done: return usb_redir_success;
      case hmp::usb_host::ControlOutcome::stalled: return usb_redir_stall;
      case hmp::usb_host::ControlOutcome::no_data_packet:
      case hmp::usb_host::ControlOutcome::no_status_stage: break;
    }
    return usb_redir_ioerror;  // the stack left the host waiting (a real controller would time out)
  }

  // Endpoint 0 for the model: a SETUP opens both directions afresh (no stall, nothing armed).
  void accept_setup() override {
    ep(0x80) = Endpoint::opened();
    ep(0x00) = Endpoint::opened();
  }
  bool stalled() override { return ep(0x80).stalled || ep(0x00).stalled; }
  hmp::usb_host::Packet* packet(std::uint8_t addr) override {
    Endpoint& e = ep(addr);
    return e.armed ? &e : nullptr;
  }
  void take(std::uint8_t addr) override { ep(addr).armed = false; }

  // ---- interrupt endpoints ----

  void pump() {
    if (!connected_) return;
    // OUT reports QEMU sent while the stack was NAKing: each completes (and is answered) once armed.
    Endpoint& out = ep(usb::kEpOut);
    while (!held_out_.empty() && out.armed && !out.stalled) {
      HeldOut& h = held_out_.front();
      const std::size_t n = std::min<std::size_t>(h.data.size(), out.len);
      std::memcpy(out.buffer, h.data.data(), n);
      out.armed = false;
      device_.on_xfer_complete(usb::kEpOut, static_cast<std::uint16_t>(n));
      usb_redir_interrupt_packet_header reply{usb::kEpOut, usb_redir_success, static_cast<std::uint16_t>(n)};
      usbredirparser_send_interrupt_packet(parser_, h.id, &reply, nullptr, 0);
      held_out_.pop_front();
    }
    // IN reports go out while QEMU receives (it polls the guest's URBs itself).
    Endpoint& in = ep(usb::kEpIn);
    while (interrupt_receiving_ && in.armed && !in.stalled) {
      in.armed = false;
      std::vector<std::uint8_t> d = in.in_data;
      usb_redir_interrupt_packet_header h{usb::kEpIn, usb_redir_success, static_cast<std::uint16_t>(d.size())};
      usbredirparser_send_interrupt_packet(parser_, in_id_++, &h, d.data(), static_cast<int>(d.size()));
      device_.on_xfer_complete(usb::kEpIn, static_cast<std::uint16_t>(d.size()));
    }
  }

  // ---- usbredir callbacks ----

  void wire_callbacks() {
    usbredirparser* p = parser_;
    p->priv = this;
    p->log_func = [](void*, int level, const char* msg) {
      if (level <= usbredirparser_warning) std::fprintf(stderr, "usb-sim: usbredir: %s\n", msg);
    };
    p->read_func = [](void* c, std::uint8_t* data, int count) -> int {
      const ssize_t n = ::recv(self(c).fd_, data, static_cast<std::size_t>(count), MSG_DONTWAIT);
      if (n == 0) return -1;  // closed
      if (n < 0) return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR ? 0 : -1;
      return static_cast<int>(n);
    };
    p->write_func = [](void* c, std::uint8_t* data, int count) -> int {
      const ssize_t n = ::send(self(c).fd_, data, static_cast<std::size_t>(count), MSG_DONTWAIT | MSG_NOSIGNAL);
      if (n < 0) return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR ? 0 : -1;
      return static_cast<int>(n);
    };
    p->hello_func = [](void* c, usb_redir_hello_header* h) {
      std::fprintf(stderr, "usb-sim: peer hello: %.64s\n", h->version);
      self(c).peer_hello_ = true;
      self(c).plug();
    };
    p->reset_func = [](void* c) {
      UsbSim& s = self(c);
      s.interrupt_receiving_ = false;
      s.held_out_.clear();
      for (auto& pair : s.eps_) pair[0] = pair[1] = Endpoint{};
      s.eps_[0][0].open = s.eps_[0][1].open = true;
      s.device_.on_bus_reset();
      s.control(0x00, 5, 1, 0, 0, nullptr);
    };
    p->set_configuration_func = [](void* c, std::uint64_t id, usb_redir_set_configuration_header* h) {
      UsbSim& s = self(c);
      const std::uint8_t status = s.control(0x00, 9, h->configuration, 0, 0, nullptr);
      s.send_interface_and_ep_info();
      usb_redir_configuration_status_header r{status, s.device_.configuration()};
      usbredirparser_send_configuration_status(s.parser_, id, &r);
    };
    p->get_configuration_func = [](void* c, std::uint64_t id) {
      UsbSim& s = self(c);
      usb_redir_configuration_status_header r{usb_redir_success, s.device_.configuration()};
      usbredirparser_send_configuration_status(s.parser_, id, &r);
    };
    p->set_alt_setting_func = [](void* c, std::uint64_t id, usb_redir_set_alt_setting_header* h) {
      UsbSim& s = self(c);
      const std::uint8_t status = s.control(0x01, 11, h->alt, h->interface, 0, nullptr);
      s.send_interface_and_ep_info();
      usb_redir_alt_setting_status_header r{status, h->interface,
                                            status == usb_redir_success ? h->alt : std::uint8_t(0)};
      usbredirparser_send_alt_setting_status(s.parser_, id, &r);
    };
    p->get_alt_setting_func = [](void* c, std::uint64_t id, usb_redir_get_alt_setting_header* h) {
      UsbSim& s = self(c);
      std::vector<std::uint8_t> in;
      const std::uint8_t status = s.control(0x81, 10, 0, h->interface, 1, nullptr, &in);
      usb_redir_alt_setting_status_header r{status, h->interface, in.empty() ? std::uint8_t(0) : in[0]};
      usbredirparser_send_alt_setting_status(s.parser_, id, &r);
    };
    p->start_interrupt_receiving_func = [](void* c, std::uint64_t id, usb_redir_start_interrupt_receiving_header* h) {
      UsbSim& s = self(c);
      const bool ok = h->endpoint == usb::kEpIn && s.device_.configuration() != 0;
      if (ok) s.interrupt_receiving_ = true;
      usb_redir_interrupt_receiving_status_header r{
          ok ? std::uint8_t(usb_redir_success) : std::uint8_t(usb_redir_inval), h->endpoint};
      usbredirparser_send_interrupt_receiving_status(s.parser_, id, &r);
    };
    p->stop_interrupt_receiving_func = [](void* c, std::uint64_t id, usb_redir_stop_interrupt_receiving_header* h) {
      UsbSim& s = self(c);
      if (h->endpoint == usb::kEpIn) s.interrupt_receiving_ = false;
      usb_redir_interrupt_receiving_status_header r{usb_redir_success, h->endpoint};
      usbredirparser_send_interrupt_receiving_status(s.parser_, id, &r);
    };
    p->control_packet_func = [](void* c, std::uint64_t id, usb_redir_control_packet_header* h, std::uint8_t* data,
                                int len) {
      UsbSim& s = self(c);
      std::vector<std::uint8_t> in;
      usb_redir_control_packet_header r = *h;
      if (h->endpoint & 0x80) {
        r.status = s.control(h->requesttype, h->request, h->value, h->index, h->length, nullptr, &in);
        r.length = static_cast<std::uint16_t>(in.size());
        usbredirparser_send_control_packet(s.parser_, id, &r, in.data(), static_cast<int>(in.size()));
      } else {
        const bool whole = len == h->length;
        r.status = whole ? s.control(h->requesttype, h->request, h->value, h->index, h->length, data)
                         : std::uint8_t(usb_redir_inval);
        usbredirparser_send_control_packet(s.parser_, id, &r, nullptr, 0);
      }
      if (data) usbredirparser_free_packet_data(s.parser_, data);
    };
    p->interrupt_packet_func = [](void* c, std::uint64_t id, usb_redir_interrupt_packet_header* h, std::uint8_t* data,
                                  int len) {
      UsbSim& s = self(c);
      if (h->endpoint == usb::kEpOut && len >= 0) {
        s.held_out_.push_back(HeldOut{id, std::vector<std::uint8_t>(data, data + len)});  // answered when taken
      } else {
        usb_redir_interrupt_packet_header r{h->endpoint, usb_redir_inval, 0};
        usbredirparser_send_interrupt_packet(s.parser_, id, &r, nullptr, 0);
      }
      if (data) usbredirparser_free_packet_data(s.parser_, data);
      s.pump();
    };
    p->cancel_data_packet_func = [](void* c, std::uint64_t id) {
      UsbSim& s = self(c);
      for (auto it = s.held_out_.begin(); it != s.held_out_.end(); ++it) {
        if (it->id != id) continue;
        usb_redir_interrupt_packet_header r{usb::kEpOut, usb_redir_cancelled, 0};
        usbredirparser_send_interrupt_packet(s.parser_, id, &r, nullptr, 0);
        s.held_out_.erase(it);
        return;
      }
    };
    // What a usb-host side never receives, or does not support: answered or ignored, never unhandled (a
    // missing callback would crash the parser on a stray packet).
    p->device_connect_func = [](void*, usb_redir_device_connect_header*) {};
    p->device_disconnect_func = [](void*) {};
    p->interface_info_func = [](void*, usb_redir_interface_info_header*) {};
    p->ep_info_func = [](void*, usb_redir_ep_info_header*) {};
    p->configuration_status_func = [](void*, std::uint64_t, usb_redir_configuration_status_header*) {};
    p->alt_setting_status_func = [](void*, std::uint64_t, usb_redir_alt_setting_status_header*) {};
    p->iso_stream_status_func = [](void*, std::uint64_t, usb_redir_iso_stream_status_header*) {};
    p->interrupt_receiving_status_func = [](void*, std::uint64_t, usb_redir_interrupt_receiving_status_header*) {};
    p->bulk_streams_status_func = [](void*, std::uint64_t, usb_redir_bulk_streams_status_header*) {};
    p->bulk_receiving_status_func = [](void*, std::uint64_t, usb_redir_bulk_receiving_status_header*) {};
    p->filter_reject_func = [](void*) {};
    p->filter_filter_func = [](void*, usbredirfilter_rule* rules, int) { free(rules); };
    p->device_disconnect_ack_func = [](void*) {};
    p->start_iso_stream_func = [](void* c, std::uint64_t id, usb_redir_start_iso_stream_header* h) {
      usb_redir_iso_stream_status_header r{usb_redir_inval, h->endpoint};
      usbredirparser_send_iso_stream_status(self(c).parser_, id, &r);
    };
    p->stop_iso_stream_func = [](void* c, std::uint64_t id, usb_redir_stop_iso_stream_header* h) {
      usb_redir_iso_stream_status_header r{usb_redir_inval, h->endpoint};
      usbredirparser_send_iso_stream_status(self(c).parser_, id, &r);
    };
    p->alloc_bulk_streams_func = [](void* c, std::uint64_t id, usb_redir_alloc_bulk_streams_header* h) {
      usb_redir_bulk_streams_status_header r{h->endpoints, 0, usb_redir_inval};
      usbredirparser_send_bulk_streams_status(self(c).parser_, id, &r);
    };
    p->free_bulk_streams_func = [](void* c, std::uint64_t id, usb_redir_free_bulk_streams_header* h) {
      usb_redir_bulk_streams_status_header r{h->endpoints, 0, usb_redir_inval};
      usbredirparser_send_bulk_streams_status(self(c).parser_, id, &r);
    };
    p->start_bulk_receiving_func = [](void* c, std::uint64_t id, usb_redir_start_bulk_receiving_header* h) {
      usb_redir_bulk_receiving_status_header r{h->stream_id, h->endpoint, usb_redir_inval};
      usbredirparser_send_bulk_receiving_status(self(c).parser_, id, &r);
    };
    p->stop_bulk_receiving_func = [](void* c, std::uint64_t id, usb_redir_stop_bulk_receiving_header* h) {
      usb_redir_bulk_receiving_status_header r{h->stream_id, h->endpoint, usb_redir_inval};
      usbredirparser_send_bulk_receiving_status(self(c).parser_, id, &r);
    };
    p->bulk_packet_func = [](void* c, std::uint64_t id, usb_redir_bulk_packet_header* h, std::uint8_t* data, int) {
      usb_redir_bulk_packet_header r = *h;
      r.status = usb_redir_inval;
      r.length = 0;
      r.length_high = 0;
      usbredirparser_send_bulk_packet(self(c).parser_, id, &r, nullptr, 0);
      if (data) usbredirparser_free_packet_data(self(c).parser_, data);
    };
    p->iso_packet_func = [](void* c, std::uint64_t, usb_redir_iso_packet_header*, std::uint8_t* data, int) {
      if (data) usbredirparser_free_packet_data(self(c).parser_, data);
    };
    p->buffered_bulk_packet_func = [](void* c, std::uint64_t, usb_redir_buffered_bulk_packet_header*,
                                      std::uint8_t* data, int) {
      if (data) usbredirparser_free_packet_data(self(c).parser_, data);
    };
  }

  struct HeldOut {
    std::uint64_t id;
    std::vector<std::uint8_t> data;
  };

  int fd_;
  usbredirparser* parser_ = nullptr;
  hmp::fw::Core core_;
  usb::Device device_;
  Endpoint eps_[16][2];
  std::chrono::nanoseconds tick_period_{};
  bool peer_hello_ = false, connected_ = false, interrupt_receiving_ = false;
  std::deque<HeldOut> held_out_;
  std::uint64_t in_id_ = 1;
};

}  // namespace

int main(int argc, char** argv) {
  std::string path;
  std::uint32_t tick_hz = hmp::fw::kDefaultTickHz;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--socket" && i + 1 < argc) {
      path = argv[++i];
    } else if (a == "--tick-hz" && i + 1 < argc) {
      tick_hz = static_cast<std::uint32_t>(std::strtoul(argv[++i], nullptr, 10));
      if (tick_hz < 100 || tick_hz > 100000) {
        std::fprintf(stderr, "error: --tick-hz %s: expected 100…100000\n", argv[i]);
        return 2;
      }
    } else {
      std::fprintf(stderr, "error: unknown argument '%s' (usage: hmp-usb-sim --socket PATH [--tick-hz N])\n", argv[i]);
      return 2;
    }
  }
  if (path.empty() || path.size() >= sizeof(sockaddr_un::sun_path)) {
    std::fprintf(stderr, "error: --socket PATH is required (a path shorter than %zu bytes)\n",
                 sizeof(sockaddr_un::sun_path));
    return 2;
  }
  struct sigaction sa {};
  sa.sa_handler = [](int sig) {
    if (sig == SIGUSR1)
      g_unplug = 1;
    else if (sig == SIGUSR2)
      g_replug = 1;
    else
      g_stop = 1;
  };
  for (int sig : {SIGUSR1, SIGUSR2, SIGTERM, SIGINT}) sigaction(sig, &sa, nullptr);

  const int listener = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::memcpy(addr.sun_path, path.c_str(), path.size());
  ::unlink(path.c_str());
  if (listener < 0 || ::bind(listener, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
      ::listen(listener, 1) != 0) {
    std::fprintf(stderr, "error: cannot listen on %s: %s\n", path.c_str(), std::strerror(errno));
    return 1;
  }
  std::fprintf(stderr, "usb-sim: listening on %s\n", path.c_str());
  const int fd = ::accept(listener, nullptr, nullptr);
  if (fd < 0) {
    std::fprintf(stderr, "usb-sim: accept: %s\n", std::strerror(errno));
    return 1;
  }
  ::close(listener);
  UsbSim sim(fd, tick_hz);
  const int rc = sim.run();
  ::close(fd);
  ::unlink(path.c_str());
  return rc;
}
