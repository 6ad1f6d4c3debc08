#pragma once
// The device's USB descriptors (USB 2.0 §9.6, HID 1.11 §6.2), byte by byte in docs/usb.md. One HID
// interface with a vendor-defined report of 64 bytes in each direction (docs/protocol.md, "USB identity"),
// an interrupt IN and an interrupt OUT endpoint of 64 bytes polled every 1 ms.
#include <cstddef>
#include <cstdint>

#include "shared/common/version.hpp"
#include "shared/protocol/protocol.hpp"

namespace hmp::fw::usb {

inline constexpr std::uint8_t kEpIn = 0x81;   // interrupt IN, endpoint 1
inline constexpr std::uint8_t kEpOut = 0x01;  // interrupt OUT, endpoint 1
inline constexpr std::uint16_t kReportSize = protocol::kReportSize;
inline constexpr std::uint8_t kInterval = 1;  // ms (full speed: frames)

// Descriptor types (USB 2.0 Table 9-5, HID 1.11 §7.1).
// Laid out by hand (descriptor bytes laid out as the USB tables list their fields), so the formatter leaves it:
// clang-format off
enum DescriptorType : std::uint8_t {
  kDevice = 1, kConfiguration = 2, kString = 3, kInterface = 4, kEndpoint = 5, kDeviceQualifier = 6,
  kHid = 0x21, kHidReport = 0x22,
};

constexpr std::uint8_t lo(std::uint16_t v) { return static_cast<std::uint8_t>(v & 0xFF); }
constexpr std::uint8_t hi(std::uint16_t v) { return static_cast<std::uint8_t>(v >> 8); }

// Vendor page 0xFF00, usage 1; 64 bytes of 0–255 in, the same out; no report ID.
inline constexpr std::uint8_t kReportDescriptor[] = {
    0x06, lo(protocol::kUsagePage), hi(protocol::kUsagePage),  // Usage Page (vendor 0xFF00)
    0x09, 0x01,                                                // Usage (1)
    0xA1, 0x01,                                                // Collection (Application)
    0x15, 0x00,                                                //   Logical Minimum (0)
    0x26, 0xFF, 0x00,                                          //   Logical Maximum (255)
    0x75, 0x08,                                                //   Report Size (8 bits)
    0x95, static_cast<std::uint8_t>(kReportSize),              //   Report Count (64)
    0x09, 0x01,                                                //   Usage (1)
    0x81, 0x02,                                                //   Input (Data, Variable, Absolute)
    0x09, 0x01,                                                //   Usage (1)
    0x91, 0x02,                                                //   Output (Data, Variable, Absolute)
    0xC0,                                                      // End Collection
};

inline constexpr std::uint8_t kDeviceDescriptor[18] = {
    18, kDevice,
    0x00, 0x02,                                        // bcdUSB 2.00
    0x00, 0x00, 0x00,                                  // class/subclass/protocol: per interface
    static_cast<std::uint8_t>(64),                     // bMaxPacketSize0
    lo(protocol::kUsbVid), hi(protocol::kUsbVid),      // idVendor 0x1209
    lo(protocol::kUsbPid), hi(protocol::kUsbPid),      // idProduct 0x0001 (test PID)
    lo(version::usb_bcd()), hi(version::usb_bcd()),    // bcdDevice: the project's version (0.1.0: 0x0010)
    1, 2, 3,                                           // iManufacturer, iProduct, iSerialNumber
    1,                                                 // bNumConfigurations
};

inline constexpr std::uint8_t kHidDescriptorOffset = 18;  // within kConfigurationDescriptor
inline constexpr std::uint8_t kConfigurationDescriptor[9 + 9 + 9 + 7 + 7] = {
    // configuration
    9, kConfiguration, 41, 0, 1, 1, 0,
    0x80,  // bmAttributes: bus powered (the motors have their own supply), no remote wake-up
    50,    // bMaxPower: 100 mA
    // interface 0: HID, no boot protocol
    9, kInterface, 0, 0, 2, 0x03, 0x00, 0x00, 0,
    // HID 1.11, no country, one report descriptor
    9, kHid, 0x11, 0x01, 0x00, 1, kHidReport, lo(sizeof kReportDescriptor), hi(sizeof kReportDescriptor),
    // endpoints: interrupt IN and OUT, 64 bytes, every 1 ms
    7, kEndpoint, kEpIn, 0x03, lo(kReportSize), hi(kReportSize), kInterval,
    7, kEndpoint, kEpOut, 0x03, lo(kReportSize), hi(kReportSize), kInterval,
};
// clang-format on

inline constexpr std::uint8_t kLangIdDescriptor[4] = {4, kString, 0x09, 0x04};  // English (United States)
inline constexpr const char* kManufacturer = "Haptic Music Player project";
inline constexpr const char* kProduct = "Haptic Music Player SPIDAR-G6 controller";

// String descriptor `text` (ASCII) as UTF-16LE into `out` (at most 126 bytes: 62 characters); its length.
std::size_t string_descriptor(const char* text, std::uint8_t (&out)[128]);

}  // namespace hmp::fw::usb
