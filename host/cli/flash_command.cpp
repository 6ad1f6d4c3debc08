// hmp flash [--board stm32f407] [--method dfu|stlink|openocd] [--firmware FILE] [--dry-run] [--timeout-s N]
// hmp flash --install-udev-rule | --print-udev-rule
// Writes the board's firmware with a Debian tool (host/flash/flash_plan.hpp), building the image first
// when it is missing or older than its sources (host/flash/firmware_image.hpp), then waits for the board
// to come back as our HID device and prints its `hmp devices` line (design §3, §13; docs/flashing.md). Tool or board
// missing: one line saying what to install or how to enter DFU mode, exit 1; bad options: exit 2.
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "host/cli/commands.hpp"
#include "host/common/child_process.hpp"
#include "host/common/error.hpp"
#include "host/common/input_file.hpp"
#include "host/common/install_layout.hpp"
#include "host/flash/firmware_image.hpp"
#include "host/flash/flash_plan.hpp"
#include "host/flash/udev_rule.hpp"  // generated from host/flash/70-hmp.rules
#include "host/transport/usb_scan.hpp"

namespace hmp::cli {
namespace {

namespace fs = std::filesystem;
using flash::Method;

struct FlashOptions {
  std::string board = "stm32f407";
  std::string method;  // empty: chosen from what is plugged in
  std::string firmware;
  bool dry_run = false;
  int timeout_s = 10;
  bool install_rule = false;
  bool print_rule = false;
};

// The source tree whose stm32f407 image is the default one ($HMP_SOURCE_DIR, else the tree this hmp was
// built in); empty for an installed hmp, which writes its installed image.
fs::path source_dir() {
  static const fs::path dir = install::source_tree().value_or(fs::path{});  // read once per run
  return dir;
}

std::string find_on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::string dirs = path != nullptr ? path : "";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t end = std::min(dirs.find(':', start), dirs.size());
    const std::string dir = dirs.substr(start, end - start);
    if (!dir.empty()) {
      const std::string candidate = dir + "/" + program;
      if (::access(candidate.c_str(), X_OK) == 0) return candidate;
    }
    start = end + 1;
  }
  return "";
}

// Runs argv with our stdin/stdout/stderr; its exit code (or -1 when it could not run or was killed).
int run_program(const std::vector<std::string>& argv, const std::string& resolved, const fs::path& cwd = {}) {
  std::fflush(stdout);
  std::fflush(stderr);
  std::string error;
  const pid_t pid = start_child({argv, resolved, cwd.string(), "", "", "", false}, error);
  return pid < 0 ? -1 : wait_child(pid);
}

int install_udev_rule() {
  std::printf("%s\nThis rule goes to %s (needs sudo).\n", flash::kUdevRule, flash::kUdevRulePath);
  if (!::isatty(STDIN_FILENO)) {
    std::fprintf(stderr, "error: --install-udev-rule asks before installing: run it from a terminal\n");
    return kExitFailure;
  }
  std::printf("Install? [y/N] ");
  std::fflush(stdout);
  char answer[16] = {};
  if (std::fgets(answer, sizeof answer, stdin) == nullptr || (answer[0] != 'y' && answer[0] != 'Y')) {
    std::printf("Nothing installed.\n");
    return kExitFailure;
  }
  char tmp[] = "/tmp/hmp-udev-XXXXXX";
  const int fd = ::mkstemp(tmp);
  if (fd < 0) throw std::runtime_error("cannot write a temporary file in /tmp");
  ::close(fd);
  std::ofstream(tmp) << flash::kUdevRule;
  const std::string sudo = find_on_path("sudo");
  if (sudo.empty()) {
    std::fprintf(stderr, "error: sudo not found — copy the rule above to %s as root\n", flash::kUdevRulePath);
    fs::remove(tmp);
    return kExitFailure;
  }
  const bool ok = run_program({"sudo", "install", "-m", "644", tmp, flash::kUdevRulePath}, sudo) == 0 &&
                  run_program({"sudo", "udevadm", "control", "--reload-rules"}, sudo) == 0 &&
                  run_program({"sudo", "udevadm", "trigger"}, sudo) == 0;
  fs::remove(tmp);
  if (!ok) {
    std::fprintf(stderr, "error: installing the rule failed (see above)\n");
    return kExitFailure;
  }
  std::printf("Installed. Unplug and replug the board.\n");
  return kExitOk;
}

// The file the method takes: --firmware (or its sibling of the other kind), else the source tree's image,
// to be built first when it is missing or older than its sources (`build` says why; empty: no build).
fs::path choose_image(const FlashOptions& o, Method method, std::string& build) {
  const char* want = flash::wants_elf(method) ? ".elf" : ".bin";
  build.clear();
  if (!o.firmware.empty()) {
    const fs::path given = o.firmware;
    check_input_file(o.firmware);  // "FILE: no such file", "FILE: is a directory", as every file read
    const std::string ext = given.extension().string();
    if (ext != ".elf" && ext != ".bin")
      throw BadInput(fmt::format("--firmware {}: expected a .elf or .bin image", o.firmware));
    if (ext == want) return given;
    fs::path sibling = given;
    sibling.replace_extension(want);
    if (fs::is_regular_file(sibling)) return sibling;
    throw BadInput(fmt::format("--firmware {}: --method {} writes a {} image, and there is no {} beside it", o.firmware,
                               flash::method_name(method), want, sibling.string()));
  }
  if (source_dir().empty()) {
    const fs::path installed = install::installed_image("stm32f407", want);
    if (fs::is_regular_file(installed)) return installed;
    throw BadInput(
        fmt::format("no firmware image: {} is missing (reinstall hmp), or give --firmware FILE", installed.string()));
  }
  if (!fs::is_directory(source_dir() / "boards" / "stm32f407")) {
    throw BadInput(
        fmt::format("no firmware image: give --firmware FILE, or HMP_SOURCE_DIR=<source tree> ({} is not one)",
                    source_dir().string()));
  }
  fs::path image = flash::default_image(source_dir(), flash::wants_elf(method));
  if (const flash::Freshness f = flash::image_freshness(image, source_dir()); f.stale) build = f.why;
  return image;
}

// The build as one shell line run in the source dir.
std::string build_line() {
  std::string line = "cd " + flash::shell_line({source_dir().string()});
  for (const auto& argv : flash::build_commands(flash::build_configured(source_dir()))) {
    line += " && " + flash::shell_line(argv);
  }
  return line;
}

int run_flash(const FlashOptions& o) {
  if (o.print_rule) {
    std::printf("%s", flash::kUdevRule);
    return kExitOk;
  }
  if (o.install_rule) return install_udev_rule();
  if (o.board != "stm32f407") throw BadInput(fmt::format("--board {}: unknown board (known: stm32f407)", o.board));
  if (o.timeout_s < 0 || o.timeout_s > 600) throw BadInput("--timeout-s: must be in [0, 600]");

  std::optional<Method> method;
  if (!o.method.empty()) {
    method = flash::parse_method(o.method);
    if (!method) throw BadInput(fmt::format("--method {}: expected dfu, stlink or openocd", o.method));
  }
  transport::ScanResult scan;
  if (!o.dry_run || !method) scan = transport::scan_usb();
  auto found = [&](transport::ProbeKind kind) {
    for (const transport::FoundProbe& p : scan.found) {
      if (p.kind == kind) return true;
    }
    return false;
  };
  if (!method)
    method =
        !found(transport::ProbeKind::stm32_dfu) && found(transport::ProbeKind::stlink) ? Method::stlink : Method::dfu;

  std::string build;  // why the image is built first; empty: it is not
  const fs::path image = choose_image(o, *method, build);
  if (build.empty()) {
    if (const std::string why = flash::image_problem(image); !why.empty())
      throw BadInput(fmt::format("{}: {}: not a firmware image for the stm32f407", image.string(), why));
  }
  const std::vector<std::string> argv = flash::command_line(*method, image.string());
  if (o.dry_run) {
    if (!build.empty()) {
      std::fprintf(stderr, "would first build %s (%s): %s\n", image.filename().c_str(), build.c_str(),
                   build_line().c_str());
    }
    std::printf("%s\n", flash::shell_line(argv).c_str());
    return kExitOk;
  }

  const flash::Tool tool = flash::tool_for(*method);
  const std::string program = find_on_path(tool.program);
  if (program.empty()) {
    std::fprintf(stderr, "error: %s\n", flash::missing_tool_message(*method).c_str());
    return kExitFailure;
  }
  if (!build.empty()) {
    std::fprintf(stderr, "building %s (%s): %s\n", image.filename().c_str(), build.c_str(), build_line().c_str());
    const std::string cmake = find_on_path("cmake");
    bool ok = !cmake.empty();
    for (const auto& step : flash::build_commands(flash::build_configured(source_dir()))) {
      if (ok) ok = run_program(step, cmake, source_dir()) == 0;  // its output goes straight to ours
    }
    if (!ok) {
      std::fprintf(stderr, "error: building the stm32f407 image failed%s\n",
                   cmake.empty() ? ": cmake not found — install it: sudo apt install cmake" : " (see above)");
      return kExitFailure;
    }
    if (!fs::is_regular_file(image)) {
      std::fprintf(stderr, "error: the stm32f407 build did not make %s\n", image.c_str());
      return kExitFailure;
    }
  }
  const bool dfu = *method == Method::dfu;
  if (!found(dfu ? transport::ProbeKind::stm32_dfu : transport::ProbeKind::stlink)) {
    std::fprintf(stderr, "error: %s\n", flash::no_board_message(*method, scan.unavailable).c_str());
    return kExitFailure;
  }
  std::fprintf(stderr, "%s\n", flash::shell_line(argv).c_str());
  if (const int rc = run_program(argv, program); rc != 0) {
    std::fprintf(stderr, "error: %s failed (exit %d)\n", tool.program, rc);
    return kExitFailure;
  }
  std::fprintf(stderr, "flashed; waiting up to %d s for the board to come back as a USB device…\n", o.timeout_s);
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(o.timeout_s);
  for (;;) {
    if (print_hid_devices(500) > 0) return kExitOk;
    if (std::chrono::steady_clock::now() >= until) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  std::fprintf(stderr,
               "warning: the board did not come back as 1209:0001 within %d s — remove the BOOT0 jumper and press "
               "RESET, or check the USB cable (hmp devices)\n",
               o.timeout_s);
  return kExitFailure;
}

}  // namespace

void register_flash(CLI::App& app, Registry& registry) {
  auto opts = std::make_shared<FlashOptions>();
  CLI::App* cmd =
      app.add_subcommand("flash", "Write the firmware to a controller board (dfu-util, st-flash or openocd)");
  cmd->add_option("--board", opts->board, "Board to flash")->capture_default_str();
  cmd->add_option("--method", opts->method, "dfu (ROM bootloader), stlink or openocd; default: what is plugged in");
  cmd->add_option("--firmware", opts->firmware,
                  "Image to write (.elf or .bin); default: the source tree's, built if needed");
  cmd->add_flag("--dry-run", opts->dry_run, "Print the command only");
  cmd->add_option("--timeout-s", opts->timeout_s, "How long to wait for the board to come back")->capture_default_str();
  cmd->add_flag("--install-udev-rule", opts->install_rule,
                "Install the udev rule (asks; uses sudo) so no root is needed");
  cmd->add_flag("--print-udev-rule", opts->print_rule, "Print the udev rule");
  cmd->callback([opts, &registry] { registry.set([opts] { return run_flash(*opts); }); });
}

}  // namespace hmp::cli
