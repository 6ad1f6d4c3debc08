#pragma once
// The USB device: endpoint 0's control state machine with the standard requests (USB 2.0 §9.4), the HID
// class requests (HID 1.11 §7.2) and the two interrupt endpoints, glued to the firmware core:
//  - a HID OUT report (interrupt endpoint or SET_REPORT) goes to Core::on_packet; the OUT endpoint is
//    armed, and a SET_REPORT accepted, only when the core's inbox has room beyond the report the other
//    path may already be bringing — until then the controller NAKs (the SET_REPORT STALLs) and the host
//    waits: no report is ever lost;
//  - the core's reports (BoardSeam::send → queue_report) wait in a queue for the IN endpoint; none is
//    dropped while the host keeps reading (a full queue refuses and the core counts it);
//  - bus reset and suspend put the outputs in the safe state (Core::on_link_lost).
// Contexts: every function here runs in one context at a time — the controller's interrupt calls the
// on_* events; a board calls poll() and queue_report() (from Core::poll's send) with that interrupt
// masked. Bounded time, no heap.
#include <cstddef>
#include <cstdint>

#include "firmware/core.hpp"
#include "firmware/usb/dcd.hpp"
#include "firmware/usb/descriptors.hpp"

namespace hmp::fw::usb {

struct Setup {
  std::uint8_t request_type = 0;  // bmRequestType
  std::uint8_t request = 0;       // bRequest
  std::uint16_t value = 0, index = 0, length = 0;
  static Setup parse(const std::uint8_t (&packet)[8]);
};

struct DeviceStats {
  std::uint32_t setups = 0;
  std::uint32_t stalls = 0;          // requests answered with STALL
  std::uint32_t aborted = 0;         // control transfers cut short by a new SETUP
  std::uint32_t out_reports = 0;     // reports handed to the core (interrupt OUT and SET_REPORT)
  std::uint32_t out_bad_length = 0;  // OUT packets that were not 64 bytes (dropped, counted)
  std::uint32_t out_held = 0;        // times the OUT endpoint stayed NAKing because the core was full
  std::uint32_t out_lost = 0;        // reports the core refused after all (never, while the arming rule holds)
  std::uint32_t in_reports = 0;      // reports the host has read
  std::uint32_t in_refused = 0;      // queue_report calls refused: the queue was full
  std::uint32_t xfer_refused = 0;    // ep_xfer calls the controller refused
  std::uint32_t bus_resets = 0, suspends = 0, resumes = 0;
};

class Device {
 public:
  static constexpr std::size_t kQueueReports = 16;

  // `serial`: the serial number string (the MCU's unique ID in hex on hardware), ASCII, ≤ 63 characters.
  Device(const Dcd& dcd, Core& core, const char* serial);
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  // Pull-up on: the host sees the device.
  void start();

  // ---- events from the controller (its interrupt) ----
  void on_bus_reset();
  void on_setup(const std::uint8_t (&packet)[8]);
  void on_xfer_complete(std::uint8_t ep_addr, std::uint16_t bytes);
  void on_suspend();
  void on_resume();

  // ---- the board's main loop (controller interrupt masked) ----
  // Arms the OUT endpoint when the core has room again; starts the next IN report.
  void poll();
  // A device report for the host; false when the queue is full.
  bool queue_report(const protocol::Report& report);
  // BoardSeam::send for a board whose transport is this device (ctx = the Device).
  static bool send_hook(void* ctx, const protocol::Report& report) {
    return static_cast<Device*>(ctx)->queue_report(report);
  }

  // ---- inspection ----
  std::uint8_t address() const { return address_; }
  std::uint8_t configuration() const { return configuration_; }
  bool suspended() const { return suspended_; }
  bool halted(std::uint8_t ep_addr) const { return ep_addr == kEpIn ? in_halted_ : ep_addr == kEpOut && out_halted_; }
  std::size_t queued_reports() const { return queue_count_; }
  const DeviceStats& stats() const { return stats_; }

 private:
  enum class Stage : std::uint8_t { idle, data_in, data_out, status_in, status_out };

  void handle_standard(const Setup& s);
  void handle_class(const Setup& s);
  void get_descriptor(const Setup& s);
  void set_configuration(std::uint8_t value);
  void set_halt(std::uint8_t ep_addr, bool halt);
  void reply(const std::uint8_t* data, std::size_t size);  // IN data stage (truncated to wLength)
  void send_next_in_packet();
  void status_in();  // a ZLP as the status stage of a no-data or OUT request
  void stall();
  bool xfer(std::uint8_t ep_addr, std::uint8_t* buffer, std::uint16_t len);
  void arm_out();
  void start_in();
  bool take_out_report(const std::uint8_t* data);  // false: the core had no room (counted)
  bool room_beyond_promised() const;
  void go_safe();

  Dcd dcd_;
  Core& core_;
  const char* serial_;

  // endpoint 0
  Stage stage_ = Stage::idle;
  Setup setup_{};
  std::uint8_t ctrl_[128]{};          // reply or OUT data of the control transfer in progress
  const std::uint8_t* tx_ = nullptr;  // the rest of the reply
  std::size_t tx_left_ = 0;
  bool tx_zlp_ = false;        // a ZLP ends the data stage (reply a multiple of 64, shorter than wLength)
  std::uint16_t rx_done_ = 0;  // OUT data stage bytes received

  // device state
  std::uint8_t address_ = 0;
  std::uint8_t configuration_ = 0;
  std::uint8_t idle_rate_ = 0;  // SET_IDLE (kept for GET_IDLE; reports are sent when there are any)
  bool suspended_ = false;
  bool in_halted_ = false, out_halted_ = false;

  // interrupt endpoints
  std::uint8_t out_buf_[kReportSize]{};
  bool out_armed_ = false;
  protocol::Report queue_[kQueueReports]{};
  std::size_t queue_head_ = 0, queue_count_ = 0;
  bool in_busy_ = false;

  DeviceStats stats_;
};

}  // namespace hmp::fw::usb
