#pragma once
// USB OTG FS core registers (RM0090 §34.16), offsets from the core's base 0x5000_0000, and the bits the
// device driver (otg_fs.hpp) uses. Device mode only; the core is clocked at 48 MHz from the PLL's Q output.
#include <cstdint>

namespace hmp::board::stm32::otg {

inline constexpr std::uintptr_t kBase = 0x50000000;
inline constexpr unsigned kIrq = 67;                 // OTG_FS global interrupt
inline constexpr unsigned kEndpoints = 4;            // EP0 … EP3 in each direction
inline constexpr std::uint32_t kFifoRamWords = 320;  // 1.25 KB shared by the RX FIFO and every TX FIFO
inline constexpr std::uint32_t kMinTxFifoWords = 16;

// ---- global ----
inline constexpr std::uint32_t kGahbcfg = 0x008, kGusbcfg = 0x00C, kGrstctl = 0x010, kGintsts = 0x014, kGintmsk = 0x018,
                               kGrxstsp = 0x020, kGrxfsiz = 0x024, kDieptxf0 = 0x028, kGccfg = 0x038;
inline constexpr std::uint32_t dieptxf(unsigned ep) { return 0x104 + 4 * (ep - 1); }  // ep 1 … 3
inline constexpr std::uint32_t kGahbcfgGintmsk = 1u << 0;
inline constexpr std::uint32_t kGusbcfgPhysel = 1u << 6, kGusbcfgFdmod = 1u << 30;
inline constexpr std::uint32_t gusbcfg_trdt(std::uint32_t v) { return v << 10; }
inline constexpr std::uint32_t kGusbcfgTrdtMask = 0xFu << 10;
inline constexpr std::uint32_t kGrstctlCsrst = 1u << 0, kGrstctlRxfflsh = 1u << 4, kGrstctlTxfflsh = 1u << 5,
                               kGrstctlAhbidl = 1u << 31;
inline constexpr std::uint32_t grstctl_txfnum(std::uint32_t n) { return n << 6; }  // 0x10: every TX FIFO
inline constexpr std::uint32_t kGccfgPwrdwn = 1u << 16, kGccfgNovbussens = 1u << 21;
// GINTSTS / GINTMSK
inline constexpr std::uint32_t kIntRxflvl = 1u << 4, kIntUsbsusp = 1u << 11, kIntUsbrst = 1u << 12,
                               kIntEnumdne = 1u << 13, kIntIepint = 1u << 18, kIntOepint = 1u << 19,
                               kIntWkupint = 1u << 31;

// GRXSTSP: the status word popped for every entry of the RX FIFO.
inline constexpr std::uint32_t kPktstsGlobalOutNak = 1, kPktstsOutData = 2, kPktstsOutComplete = 3,
                               kPktstsSetupComplete = 4, kPktstsSetupData = 6;

// ---- device ----
inline constexpr std::uint32_t kDcfg = 0x800, kDctl = 0x804, kDiepmsk = 0x810, kDoepmsk = 0x814, kDaint = 0x818,
                               kDaintmsk = 0x81C;
inline constexpr std::uint32_t kDcfgDspdFull = 0x3, kDcfgDadMask = 0x7Fu << 4;
inline constexpr std::uint32_t dcfg_dad(std::uint32_t a) { return (a & 0x7Fu) << 4; }
inline constexpr std::uint32_t kDctlSdis = 1u << 1, kDctlCginak = 1u << 8;
inline constexpr std::uint32_t diepctl(unsigned ep) { return 0x900 + 0x20 * ep; }
inline constexpr std::uint32_t diepint(unsigned ep) { return 0x908 + 0x20 * ep; }
inline constexpr std::uint32_t dieptsiz(unsigned ep) { return 0x910 + 0x20 * ep; }
inline constexpr std::uint32_t dtxfsts(unsigned ep) { return 0x918 + 0x20 * ep; }
inline constexpr std::uint32_t doepctl(unsigned ep) { return 0xB00 + 0x20 * ep; }
inline constexpr std::uint32_t doepint(unsigned ep) { return 0xB08 + 0x20 * ep; }
inline constexpr std::uint32_t doeptsiz(unsigned ep) { return 0xB10 + 0x20 * ep; }
inline constexpr std::uint32_t fifo(unsigned ep) { return 0x1000 + 0x1000 * ep; }
inline constexpr std::uint32_t kPcgcctl = 0xE00;
// DIEPCTLx / DOEPCTLx
inline constexpr std::uint32_t kEpctlUsbaep = 1u << 15, kEpctlStall = 1u << 21, kEpctlCnak = 1u << 26,
                               kEpctlSnak = 1u << 27, kEpctlSd0pid = 1u << 28, kEpctlEpdis = 1u << 30,
                               kEpctlEpena = 1u << 31;
inline constexpr std::uint32_t epctl_eptyp(std::uint32_t t) { return t << 18; }
inline constexpr std::uint32_t diepctl_txfnum(std::uint32_t n) { return n << 22; }
// DIEPINTx / DOEPINTx
inline constexpr std::uint32_t kEpintXfrc = 1u << 0, kEpintEpdisd = 1u << 1, kDoepintStup = 1u << 3,
                               kDoepintB2bstup = 1u << 6;
// DIEPTSIZx / DOEPTSIZx
inline constexpr std::uint32_t eptsiz(std::uint32_t packets, std::uint32_t bytes) { return packets << 19 | bytes; }
inline constexpr std::uint32_t doeptsiz0_stupcnt(std::uint32_t n) { return n << 29; }

}  // namespace hmp::board::stm32::otg
