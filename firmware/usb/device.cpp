#include "firmware/usb/device.hpp"

namespace hmp::fw::usb {

namespace {

// bmRequestType fields (USB 2.0 Table 9-2).
constexpr std::uint8_t kTypeMask = 0x60, kTypeStandard = 0x00, kTypeClass = 0x20;
constexpr std::uint8_t kRecipientMask = 0x1F, kToDevice = 0, kToInterface = 1, kToEndpoint = 2;

// Standard requests (Table 9-4) and features (Table 9-6).
enum : std::uint8_t {
  kGetStatus = 0,
  kClearFeature = 1,
  kSetFeature = 3,
  kSetAddress = 5,
  kGetDescriptor = 6,
  kGetConfiguration = 8,
  kSetConfiguration = 9,
  kGetInterface = 10,
  kSetInterface = 11,
};
constexpr std::uint16_t kEndpointHalt = 0;

// HID class requests (HID 1.11 §7.2).
enum : std::uint8_t { kGetReport = 1, kGetIdle = 2, kSetReport = 9, kSetIdle = 10 };
constexpr std::uint8_t kReportTypeInput = 1, kReportTypeOutput = 2;

constexpr std::uint16_t le16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | p[1] << 8); }

}  // namespace

Setup Setup::parse(const std::uint8_t (&p)[8]) { return Setup{p[0], p[1], le16(p + 2), le16(p + 4), le16(p + 6)}; }

std::size_t string_descriptor(const char* text, std::uint8_t (&out)[128]) {
  std::size_t n = 2;
  for (const char* c = text; *c != '\0' && n + 2 <= sizeof out; ++c) {
    out[n++] = static_cast<std::uint8_t>(*c & 0x7F);  // ASCII only: anything else would be a UTF-16 lie
    out[n++] = 0;
  }
  out[0] = static_cast<std::uint8_t>(n);
  out[1] = kString;
  return n;
}

Device::Device(const Dcd& dcd, Core& core, const char* serial) : dcd_(dcd), core_(core), serial_(serial) {}

void Device::start() {
  if (dcd_.connect) dcd_.connect(dcd_.ctx, true);
}

bool Device::xfer(std::uint8_t ep_addr, std::uint8_t* buffer, std::uint16_t len) {
  if (dcd_.ep_xfer && dcd_.ep_xfer(dcd_.ctx, ep_addr, buffer, len)) return true;
  ++stats_.xfer_refused;
  return false;
}

void Device::go_safe() { core_.on_link_lost(); }

// ---- bus events ----

void Device::on_bus_reset() {
  ++stats_.bus_resets;
  if (configuration_ != 0 && dcd_.ep_close) {
    dcd_.ep_close(dcd_.ctx, kEpIn);
    dcd_.ep_close(dcd_.ctx, kEpOut);
  }
  stage_ = Stage::idle;
  address_ = 0;
  configuration_ = 0;
  idle_rate_ = 0;
  suspended_ = false;
  in_halted_ = out_halted_ = false;
  out_armed_ = in_busy_ = false;
  queue_head_ = queue_count_ = 0;  // a new host session: what the old one did not read is stale
  go_safe();
}

void Device::on_suspend() {
  ++stats_.suspends;
  suspended_ = true;
  go_safe();
}

void Device::on_resume() {
  ++stats_.resumes;
  suspended_ = false;
  start_in();
}

// ---- endpoint 0 ----

void Device::stall() {
  ++stats_.stalls;
  stage_ = Stage::idle;
  if (dcd_.ep_stall) dcd_.ep_stall(dcd_.ctx, 0x00);  // both directions, until the next SETUP
}

void Device::status_in() {
  stage_ = Stage::status_in;
  xfer(kDirIn, nullptr, 0);
}

void Device::reply(const std::uint8_t* data, std::size_t size) {
  const std::size_t sent = size < setup_.length ? size : setup_.length;
  tx_ = data;
  tx_left_ = sent;
  // The host knows the transfer ended from a short packet or from having all wLength bytes: a reply
  // shorter than wLength that fills its last packet needs a zero-length one after it.
  tx_zlp_ = sent < setup_.length && sent % kEp0Size == 0;
  stage_ = Stage::data_in;
  send_next_in_packet();
}

void Device::send_next_in_packet() {
  const std::uint16_t n = static_cast<std::uint16_t>(tx_left_ < kEp0Size ? tx_left_ : kEp0Size);
  if (n == 0) tx_zlp_ = false;  // this packet is the ZLP
  // The controller copies from the stack's buffer; descriptors live in flash, hence the cast.
  xfer(kDirIn, const_cast<std::uint8_t*>(tx_), n);
  tx_ += n;
  tx_left_ -= n;
}

void Device::on_setup(const std::uint8_t (&packet)[8]) {
  ++stats_.setups;
  if (stage_ != Stage::idle) ++stats_.aborted;  // a new SETUP ends whatever was in progress
  stage_ = Stage::idle;
  tx_left_ = 0;
  tx_zlp_ = false;
  setup_ = Setup::parse(packet);
  switch (setup_.request_type & kTypeMask) {
    case kTypeStandard: handle_standard(setup_); break;
    case kTypeClass: handle_class(setup_); break;
    default: stall(); break;  // vendor requests: none
  }
}

void Device::handle_standard(const Setup& s) {
  const std::uint8_t recipient = s.request_type & kRecipientMask;
  const bool in = (s.request_type & kDirIn) != 0;
  const bool configured = configuration_ != 0;
  switch (s.request) {
    case kGetDescriptor:
      if (!in) break;
      get_descriptor(s);
      return;
    case kSetAddress:
      if (in || recipient != kToDevice || s.value > 127 || s.index != 0 || s.length != 0 || configured) break;
      address_ = static_cast<std::uint8_t>(s.value);
      if (dcd_.set_address) dcd_.set_address(dcd_.ctx, address_);  // before the status stage (dcd.hpp)
      status_in();
      return;
    case kGetConfiguration:
      if (!in || recipient != kToDevice) break;
      ctrl_[0] = configuration_;
      reply(ctrl_, 1);
      return;
    case kSetConfiguration:
      if (in || recipient != kToDevice || s.value > 1 || address_ == 0) break;
      set_configuration(static_cast<std::uint8_t>(s.value));
      status_in();
      return;
    case kGetStatus:
      if (!in || s.length < 2) break;
      ctrl_[0] = ctrl_[1] = 0;  // device: bus powered, no remote wake-up; interface: reserved zeros
      if (recipient == kToInterface && (!configured || s.index != 0)) break;
      if (recipient == kToEndpoint) {
        const auto ep = static_cast<std::uint8_t>(s.index);
        if (ep == 0x00 || ep == kDirIn) {
          // endpoint 0 is never halted (a protocol stall is not a halt)
        } else if (configured && (ep == kEpIn || ep == kEpOut)) {
          ctrl_[0] = halted(ep) ? 1 : 0;
        } else {
          break;
        }
      } else if (recipient != kToDevice && recipient != kToInterface) {
        break;
      }
      reply(ctrl_, 2);
      return;
    case kClearFeature:
    case kSetFeature: {
      // Only ENDPOINT_HALT on our two data endpoints (no remote wake-up, no test mode).
      const auto ep = static_cast<std::uint8_t>(s.index);
      if (in || recipient != kToEndpoint || s.value != kEndpointHalt || !configured || (ep != kEpIn && ep != kEpOut))
        break;
      set_halt(ep, s.request == kSetFeature);
      status_in();
      return;
    }
    case kGetInterface:
      if (!in || recipient != kToInterface || !configured || s.index != 0) break;
      ctrl_[0] = 0;
      reply(ctrl_, 1);
      return;
    case kSetInterface:
      if (in || recipient != kToInterface || !configured || s.index != 0 || s.value != 0) break;
      // The one alternate setting again: the endpoints start over, as after SET_CONFIGURATION.
      set_halt(kEpIn, false);
      set_halt(kEpOut, false);
      status_in();
      return;
    default: break;
  }
  stall();
}

void Device::get_descriptor(const Setup& s) {
  const auto type = static_cast<std::uint8_t>(s.value >> 8);
  const auto index = static_cast<std::uint8_t>(s.value & 0xFF);
  const std::uint8_t recipient = s.request_type & kRecipientMask;
  if (recipient == kToInterface) {  // HID class descriptors are asked of the interface (HID 1.11 §7.1.1)
    if (s.index != 0) return stall();
    if (type == kHidReport) return reply(kReportDescriptor, sizeof kReportDescriptor);
    if (type == kHid) return reply(kConfigurationDescriptor + kHidDescriptorOffset, 9);
    return stall();
  }
  if (recipient != kToDevice) return stall();
  switch (type) {
    case kDevice: return reply(kDeviceDescriptor, sizeof kDeviceDescriptor);
    case kConfiguration:
      if (index != 0) return stall();
      return reply(kConfigurationDescriptor, sizeof kConfigurationDescriptor);
    case kString: {
      if (index == 0) return reply(kLangIdDescriptor, sizeof kLangIdDescriptor);
      const char* text = index == 1 ? kManufacturer : index == 2 ? kProduct : index == 3 ? serial_ : nullptr;
      if (text == nullptr) return stall();
      return reply(ctrl_, string_descriptor(text, ctrl_));
    }
    default:
      // DEVICE_QUALIFIER included: a full-speed-only device has none, and STALL says so (USB 2.0 §9.6.2).
      return stall();
  }
}

void Device::handle_class(const Setup& s) {
  if ((s.request_type & kRecipientMask) != kToInterface || s.index != 0) return stall();
  const bool in = (s.request_type & kDirIn) != 0;
  const auto report_type = static_cast<std::uint8_t>(s.value >> 8);
  switch (s.request) {
    case kSetIdle:
      if (in) break;
      idle_rate_ = static_cast<std::uint8_t>(s.value >> 8);
      status_in();
      return;
    case kGetIdle:
      if (!in) break;
      ctrl_[0] = idle_rate_;
      reply(ctrl_, 1);
      return;
    case kGetReport:
      // hidapi's fallback for reading: the oldest queued report. With none waiting there is nothing to
      // say, and a STALL says that (the interrupt endpoint is the way to wait for reports).
      if (!in || report_type != kReportTypeInput || queue_count_ == 0 || in_busy_) break;
      for (std::size_t i = 0; i < kReportSize; ++i) ctrl_[i] = queue_[queue_head_][i];
      queue_head_ = (queue_head_ + 1) % kQueueReports;
      --queue_count_;
      ++stats_.in_reports;
      reply(ctrl_, kReportSize);
      return;
    case kSetReport:
      // hidapi's fallback for writing. The control pipe has no NAK to wait with: without room in the
      // core the request is refused with a STALL (and the host may retry) rather than the report lost.
      if (in || report_type != kReportTypeOutput || s.length != kReportSize || !room_beyond_promised()) break;
      stage_ = Stage::data_out;
      rx_done_ = 0;
      xfer(0x00, ctrl_, kEp0Size);
      return;
    default: break;
  }
  stall();
}

void Device::on_xfer_complete(std::uint8_t ep_addr, std::uint16_t bytes) {
  switch (ep_addr) {
    case kDirIn:  // endpoint 0 IN
      if (stage_ == Stage::data_in) {
        if (tx_left_ > 0 || tx_zlp_) {
          send_next_in_packet();
        } else {
          stage_ = Stage::status_out;  // the host's ZLP ends the transfer
          xfer(0x00, ctrl_, kEp0Size);
        }
      } else if (stage_ == Stage::status_in) {
        stage_ = Stage::idle;
      }
      return;
    case 0x00:  // endpoint 0 OUT
      if (stage_ == Stage::data_out) {
        if (bytes > kEp0Size || rx_done_ + bytes > setup_.length) return stall();
        // Received into ctrl_ + rx_done_ by the arm below (the first packet lands at ctrl_).
        rx_done_ = static_cast<std::uint16_t>(rx_done_ + bytes);
        if (rx_done_ < setup_.length && bytes == kEp0Size) {
          xfer(0x00, ctrl_ + rx_done_, kEp0Size);
          return;
        }
        if (rx_done_ != kReportSize) return stall();  // short: not a whole report
        if (!take_out_report(ctrl_)) return stall();  // not taken: the host is told, and may send it again
        status_in();
      } else if (stage_ == Stage::status_out) {
        stage_ = Stage::idle;
      }
      return;
    case kEpOut:
      out_armed_ = false;
      if (bytes == kReportSize) {
        take_out_report(out_buf_);
      } else {
        ++stats_.out_bad_length;
      }
      arm_out();
      return;
    case kEpIn:
      if (in_busy_) {
        in_busy_ = false;
        queue_head_ = (queue_head_ + 1) % kQueueReports;
        --queue_count_;
        ++stats_.in_reports;
      }
      start_in();
      return;
    default: return;
  }
}

// ---- configuration and data endpoints ----

void Device::set_configuration(std::uint8_t value) {
  if (configuration_ != 0 && dcd_.ep_close) {
    dcd_.ep_close(dcd_.ctx, kEpIn);
    dcd_.ep_close(dcd_.ctx, kEpOut);
  }
  configuration_ = value;
  in_halted_ = out_halted_ = false;
  out_armed_ = in_busy_ = false;
  if (value == 0) return;
  if (dcd_.ep_open) {
    dcd_.ep_open(dcd_.ctx, kEpIn, EpType::interrupt, kReportSize);
    dcd_.ep_open(dcd_.ctx, kEpOut, EpType::interrupt, kReportSize);
  }
  arm_out();
  start_in();
}

void Device::set_halt(std::uint8_t ep_addr, bool halt) {
  bool& flag = ep_addr == kEpIn ? in_halted_ : out_halted_;
  flag = halt;
  if (halt) {
    if (dcd_.ep_stall) dcd_.ep_stall(dcd_.ctx, ep_addr);
    return;
  }
  // CLEAR_FEATURE(ENDPOINT_HALT) also resets the data toggle (USB 2.0 §9.4.5), even on an endpoint
  // that was not halted: the controller does both.
  if (dcd_.ep_clear_stall) dcd_.ep_clear_stall(dcd_.ctx, ep_addr);
  if (ep_addr == kEpIn) {
    in_busy_ = false;  // a report in the FIFO when the halt came is sent again
    start_in();
  } else {
    out_armed_ = false;
    arm_out();
  }
}

bool Device::take_out_report(const std::uint8_t* data) {
  protocol::Report report;
  for (std::size_t i = 0; i < kReportSize; ++i) report[i] = data[i];
  if (core_.on_packet(report)) {
    ++stats_.out_reports;
    return true;
  }
  ++stats_.out_lost;  // cannot happen while room_beyond_promised() holds; counted if it ever does
  return false;
}

// Room in the core for one more report besides those already promised one: the armed OUT endpoint may
// complete at any time, and a SET_REPORT accepted at its SETUP is coming in its data stage. Both paths
// check this, so the two never count on the same last slot.
bool Device::room_beyond_promised() const {
  const std::uint32_t promised = (out_armed_ ? 1u : 0u) + (stage_ == Stage::data_out ? 1u : 0u);
  return core_.inbox_free() > promised;
}

void Device::arm_out() {
  if (configuration_ == 0 || out_halted_ || out_armed_) return;
  if (!room_beyond_promised()) {
    ++stats_.out_held;  // the controller NAKs until poll() finds room
    return;
  }
  out_armed_ = xfer(kEpOut, out_buf_, kReportSize);
}

void Device::start_in() {
  if (configuration_ == 0 || in_halted_ || in_busy_ || suspended_ || queue_count_ == 0) return;
  in_busy_ = xfer(kEpIn, queue_[queue_head_], kReportSize);
}

void Device::poll() {
  if (!out_armed_ && configuration_ != 0 && !out_halted_ && room_beyond_promised()) {
    out_armed_ = xfer(kEpOut, out_buf_, kReportSize);
  }
  start_in();
}

bool Device::queue_report(const protocol::Report& report) {
  if (queue_count_ == kQueueReports) {
    ++stats_.in_refused;
    return false;
  }
  protocol::Report& slot = queue_[(queue_head_ + queue_count_) % kQueueReports];
  for (std::size_t i = 0; i < kReportSize; ++i) slot[i] = report[i];
  ++queue_count_;
  start_in();
  return true;
}

}  // namespace hmp::fw::usb
