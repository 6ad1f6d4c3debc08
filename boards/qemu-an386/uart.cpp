#include "uart.hpp"

#include "registers.hpp"

namespace hmp::board {
namespace {

constexpr std::uintptr_t kData = 0x000, kState = 0x004, kCtrl = 0x008, kIntStatus = 0x00C, kBaudDiv = 0x010;
constexpr std::uint32_t kStateTxFull = 1u << 0, kStateRxFull = 1u << 1, kStateTxOverrun = 1u << 2,
                        kStateRxOverrun = 1u << 3;
constexpr std::uint32_t kCtrlTxEnable = 1u << 0, kCtrlRxEnable = 1u << 1, kCtrlTxInt = 1u << 2, kCtrlRxInt = 1u << 3;
constexpr std::uint32_t kIntTx = 1u << 0, kIntRx = 1u << 1, kIntTxOverrun = 1u << 2, kIntRxOverrun = 1u << 3;
constexpr std::uint32_t kMinBaudDiv = 16;

}  // namespace

void CmsdkUart::init(std::uint32_t pclk_hz, std::uint32_t baud) const {
  reg(base_ + kCtrl) = 0;
  std::uint32_t div = baud != 0 ? pclk_hz / baud : kMinBaudDiv;
  reg(base_ + kBaudDiv) = div < kMinBaudDiv ? kMinBaudDiv : div;
  reg(base_ + kState) = kStateTxOverrun | kStateRxOverrun;  // clear stale overrun flags (write 1 to clear)
  reg(base_ + kIntStatus) = kIntTx | kIntRx | kIntTxOverrun | kIntRxOverrun;  // and stale interrupts
  reg(base_ + kCtrl) = kCtrlTxEnable | kCtrlRxEnable | kCtrlTxInt | kCtrlRxInt;
}

bool CmsdkUart::rx_full() const { return (reg(base_ + kState) & kStateRxFull) != 0; }
std::uint8_t CmsdkUart::read() const { return static_cast<std::uint8_t>(reg(base_ + kData)); }
bool CmsdkUart::tx_full() const { return (reg(base_ + kState) & kStateTxFull) != 0; }
void CmsdkUart::write(std::uint8_t byte) const { reg(base_ + kData) = byte; }

bool CmsdkUart::take_rx_overrun() const {
  if ((reg(base_ + kState) & kStateRxOverrun) == 0) return false;
  reg(base_ + kState) = kStateRxOverrun;
  return true;
}

void CmsdkUart::clear_rx_interrupt() const { reg(base_ + kIntStatus) = kIntRx; }
void CmsdkUart::clear_tx_interrupt() const { reg(base_ + kIntStatus) = kIntTx; }

void CmsdkUart::pause_rx() const { nvic::disable(rx_irq_); }
void CmsdkUart::resume_rx() const {
  nvic::enable(rx_irq_);
  nvic::set_pending(rx_irq_);  // the waiting byte's interrupt was already cleared
}
void CmsdkUart::kick_tx() const { nvic::set_pending(tx_irq_); }

}  // namespace hmp::board
