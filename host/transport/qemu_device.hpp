#pragma once
// `--device qemu` (design §3, §13): boots the qemu-an386 firmware image in qemu-system-arm and talks to
// it over its UART0 as a serial link (boards/qemu-an386/README.md). The emulator connects to a
// unix-domain socket this object listens on in a private temporary folder, so the link exists before
// the firmware runs its first instruction. `--device qemu:net` talks to it over its Ethernet controller
// instead (a report per frame, ether_transport.hpp): the emulated UART takes one byte per round trip of
// the emulator's main loop (~90 µs), the network a whole report. The emulator runs in its own process group (a Ctrl-C
// on the terminal reaches only hmp, which stops the device cleanly) and is stopped when this object goes.
//
// The image: $HMP_QEMU_ELF, else, run from a build tree, its source tree's qemu-an386 cross tree
// (build/qemu-an386/boards/qemu-an386/hmp_fw_qemu_an386-VERSION.elf), else the installed one
// (share/hmp/firmware/, host/common/install_layout.hpp).
// The emulator: $QEMU_SYSTEM_ARM, else qemu-system-arm on the PATH.
#include <sys/types.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "host/transport/transport.hpp"
#include "shared/synth/tick_rate.hpp"

namespace hmp::transport {

class QemuDevice {
 public:
  struct Options {
    std::uint32_t tick_hz = synth::kNominalTickHz;
    bool net = false;  // the Ethernet link instead of UART0
  };
  explicit QemuDevice(const Options& options);
  ~QemuDevice();
  QemuDevice(const QemuDevice&) = delete;
  QemuDevice& operator=(const QemuDevice&) = delete;

  // Starts the emulator and returns the connected link. Throws TransportError (no image, no
  // emulator, no connection within 10 s) with a one-line message.
  std::unique_ptr<Transport> connect();
  // The firmware's semihosting output so far (its log): for messages and tests.
  std::string log() const;
  const std::string& image() const { return image_; }

 private:
  std::unique_ptr<Transport> connect_uart(std::vector<std::string> args);
  std::unique_ptr<Transport> connect_net(std::vector<std::string> args);
  void start(const std::vector<std::string>& args);  // the emulator with these arguments
  // Stops the emulator and throws `what`, with the first line of its log when it wrote one.
  [[noreturn]] void fail(const std::string& what);
  void stop();
  Options options_;
  std::string image_;
  std::string dir_;
  int listen_fd_ = -1;
  pid_t pid_ = -1;
};

// Where the image is looked for (see above); empty when neither place has one.
std::string find_qemu_image();
// The emulator to run: $QEMU_SYSTEM_ARM, else qemu-system-arm (found on the PATH when it runs).
std::string qemu_emulator();

}  // namespace hmp::transport
