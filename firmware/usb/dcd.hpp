#pragma once
// firmware/usb/ owns the device side of USB: a board-independent USB 2.0 full-speed device stack (control
// endpoint 0, the standard requests of USB 2.0 chapter 9, the HID class of HID 1.11) and its glue to the
// firmware core. It knows no controller: this file is the seam to one (a device controller driver, DCD),
// in the style of firmware/board.hpp — a struct of function pointers, no virtual calls, no board header.
// Each board that speaks USB fills one in: the STM32F407's OTG FS driver, the usbredir rig that shows the
// stack to a Linux guest, the scripted host of the unit tests.
//
// Contract (both directions):
//  - Packets, not transfers. Every ep_xfer moves at most one packet (≤ the endpoint's max packet size):
//    the stack splits a long control reply into packets itself and sends the zero-length packet (ZLP)
//    when one is due. So a controller never has to split or join, and it reports one completion per call.
//  - Buffers belong to the stack and stay valid until the matching xfer_complete (or a bus reset or
//    ep_close). IN: the controller copies `len` bytes into its FIFO (at once or later). OUT: the
//    controller writes up to `len` bytes and reports how many came (a short or zero-length packet is a
//    normal completion).
//  - An OUT endpoint that is not armed answers NAK. The stack arms the HID OUT endpoint only when the core
//    can take the next report: NAK is the flow control, no report is ever lost.
//  - SET_ADDRESS: the stack calls set_address(addr) when the request's SETUP arrives, before it queues the
//    status stage's ZLP. A controller that applies the address in hardware only after the status stage
//    (the OTG FS core does so by itself) writes it at once; one that must not answer on the new address
//    before the status stage ends keeps it until the ZLP's completion. Both are correct USB.
//  - ep_stall on endpoint 0 stalls both directions until the next SETUP, which the controller must always
//    accept (USB 2.0 §8.5.3.4). ep_clear_stall on a data endpoint resets its data toggle to DATA0 and
//    cancels a transfer armed or queued on it (the stack arms or sends again); ep_stall cancels it too.
//  - Events go into the stack by calling hmp::fw::usb::Device's on_* functions (device.hpp) from the
//    controller's interrupt, one at a time (never re-entered). Commands may be called from inside them.
#include <cstdint>

namespace hmp::fw::usb {

enum class EpType : std::uint8_t { control = 0, isochronous = 1, bulk = 2, interrupt = 3 };

inline constexpr std::uint8_t kDirIn = 0x80;  // bit 7 of an endpoint address: device → host
inline constexpr std::uint16_t kEp0Size = 64;

struct Dcd {
  void* ctx = nullptr;  // handed back to every call

  // Pull-up on (the host sees the device) or off.
  void (*connect)(void* ctx, bool on) = nullptr;
  // The address from SET_ADDRESS (see the contract above for when it takes effect).
  void (*set_address)(void* ctx, std::uint8_t address) = nullptr;
  // Data endpoints after SET_CONFIGURATION (and closed again by SET_CONFIGURATION 0 or a bus reset).
  // Endpoint 0 is always open.
  void (*ep_open)(void* ctx, std::uint8_t ep_addr, EpType type, std::uint16_t max_packet) = nullptr;
  void (*ep_close)(void* ctx, std::uint8_t ep_addr) = nullptr;
  void (*ep_stall)(void* ctx, std::uint8_t ep_addr) = nullptr;
  void (*ep_clear_stall)(void* ctx, std::uint8_t ep_addr) = nullptr;
  // One packet: IN sends `len` bytes of `buffer` (len 0: a ZLP); OUT arms the endpoint for up to `len`.
  // false: the controller refused (endpoint not open, or busy): the stack counts it and goes on.
  bool (*ep_xfer)(void* ctx, std::uint8_t ep_addr, std::uint8_t* buffer, std::uint16_t len) = nullptr;
};

}  // namespace hmp::fw::usb
