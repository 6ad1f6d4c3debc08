// host/flash: the flashing tools' command lines as their documentation and boards/stm32f407/README.md
// give them (dfu-util(1): -d VID:PID, -a alt, -s address[:leave], -D file; st-flash: [--reset] write
// FILE ADDR; OpenOCD's `program FILE verify reset exit`), shell quoting that survives a shell, and the
// USB ids hmp looks for, the image build's commands, the one-line errors, and the udev rule
// (host/flash/70-hmp.rules) as compiled into hmp.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "host/flash/flash_plan.hpp"
#include "host/flash/udev_rule.hpp"
#include "host/transport/usb_scan.hpp"

namespace {

namespace flash = hmp::flash;
namespace transport = hmp::transport;
using Args = std::vector<std::string>;

TEST(FlashPlan, CommandLinesAsDocumented) {
  EXPECT_EQ(flash::command_line(flash::Method::dfu, "fw.bin"),
            (Args{"dfu-util", "-d", "0483:df11", "-a", "0", "-s", "0x08000000:leave", "-D", "fw.bin"}));
  EXPECT_EQ(flash::command_line(flash::Method::stlink, "fw.bin"),
            (Args{"st-flash", "--reset", "write", "fw.bin", "0x8000000"}));
  EXPECT_EQ(flash::command_line(flash::Method::openocd, "fw.elf"),
            (Args{"openocd", "-f", "board/stm32f4discovery.cfg", "-c", "program fw.elf verify reset exit"}));
  EXPECT_FALSE(flash::wants_elf(flash::Method::dfu));
  EXPECT_FALSE(flash::wants_elf(flash::Method::stlink));
  EXPECT_TRUE(flash::wants_elf(flash::Method::openocd));
  EXPECT_STREQ(flash::tool_for(flash::Method::stlink).package, "stlink-tools");
  EXPECT_STREQ(flash::tool_for(flash::Method::dfu).program, "dfu-util");
}

TEST(FlashPlan, MethodNamesRoundTripAndNothingElseParses) {
  for (flash::Method m : {flash::Method::dfu, flash::Method::stlink, flash::Method::openocd}) {
    EXPECT_EQ(flash::parse_method(flash::method_name(m)), m);
  }
  for (const char* bad : {"", "DFU", "st-link", "jtag", "dfu "})
    EXPECT_FALSE(flash::parse_method(bad).has_value()) << bad;
}

// The quoted line, given to /bin/sh, reaches a program as exactly the original arguments.
TEST(FlashPlan, ShellLineSurvivesTheShell) {
  const Args argv = {"printf", "[%s]", "plain", "with space", "it's", "$HOME", "a\"b", "*", ""};
  const std::string line = flash::shell_line(argv);
  FILE* p = ::popen(line.c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string got;
  char buf[256];
  while (std::fgets(buf, sizeof buf, p) != nullptr) got += buf;
  ::pclose(p);
  EXPECT_EQ(got, "[plain][with space][it's][$HOME][a\"b][*][]") << line;
  EXPECT_EQ(flash::shell_line({"dfu-util", "-s", "0x08000000:leave"}), "dfu-util -s 0x08000000:leave");
}

TEST(FlashPlan, KnownUsbIds) {
  const transport::UsbId* dfu = transport::known_id(0x0483, 0xdf11);
  ASSERT_NE(dfu, nullptr);
  EXPECT_EQ(dfu->kind, transport::ProbeKind::stm32_dfu);
  ASSERT_NE(transport::known_id(0x0483, 0x3748), nullptr);
  EXPECT_EQ(transport::known_id(0x0483, 0x3748)->kind, transport::ProbeKind::stlink);
  EXPECT_EQ(transport::known_id(0x1209, 0x0001), nullptr) << "our own device is HID, listed by hidapi";
  EXPECT_EQ(transport::known_id(0x0483, 0x5740), nullptr);
  const transport::FoundProbe p{transport::ProbeKind::stm32_dfu, "STM32 in DFU mode", 1, 5};
  EXPECT_EQ(transport::describe(p), "STM32 in DFU mode on bus 1 device 5 — run hmp flash");
}

// Each method with the image kind it takes; the image path goes through unchanged (no quoting in argv).
TEST(FlashPlan, EachMethodWithItsImageKind) {
  const std::string bin = "/tmp/my fw/hmp_fw_stm32f407.bin", elf = "/tmp/my fw/hmp_fw_stm32f407.elf";
  // dfu-util(1): -d vendor:product, -a alt setting (0: internal flash), -s address[:modifiers], -D download.
  EXPECT_EQ(flash::command_line(flash::Method::dfu, bin),
            (Args{"dfu-util", "-d", "0483:df11", "-a", "0", "-s", "0x08000000:leave", "-D", bin}));
  // st-flash(1): st-flash [--reset] write FILE ADDR.
  EXPECT_EQ(flash::command_line(flash::Method::stlink, bin), (Args{"st-flash", "--reset", "write", bin, "0x8000000"}));
  // OpenOCD manual, "program": program filename [preverify] [verify] [reset] [exit] [offset].
  EXPECT_EQ(flash::command_line(flash::Method::openocd, elf),
            (Args{"openocd", "-f", "board/stm32f4discovery.cfg", "-c", "program " + elf + " verify reset exit"}));
  EXPECT_EQ(flash::shell_line(flash::command_line(flash::Method::openocd, "fw.elf")),
            "openocd -f board/stm32f4discovery.cfg -c 'program fw.elf verify reset exit'");
  EXPECT_STREQ(flash::tool_for(flash::Method::openocd).program, "openocd");
  EXPECT_STREQ(flash::tool_for(flash::Method::openocd).package, "openocd");
  EXPECT_STREQ(flash::tool_for(flash::Method::stlink).program, "st-flash");
  EXPECT_STREQ(flash::tool_for(flash::Method::dfu).package, "dfu-util");
}

TEST(FlashPlan, BuildCommands) {
  EXPECT_EQ(flash::build_commands(true), (std::vector<Args>{{"cmake", "--build", "--preset", "stm32f407"}}));
  EXPECT_EQ(flash::build_commands(false),
            (std::vector<Args>{{"cmake", "--preset", "stm32f407"}, {"cmake", "--build", "--preset", "stm32f407"}}));
}

TEST(FlashPlan, OneLineErrors) {
  EXPECT_EQ(flash::missing_tool_message(flash::Method::dfu),
            "dfu-util not found — install it: sudo apt install dfu-util");
  EXPECT_EQ(flash::missing_tool_message(flash::Method::stlink),
            "st-flash not found — install it: sudo apt install stlink-tools");
  EXPECT_EQ(flash::missing_tool_message(flash::Method::openocd),
            "openocd not found — install it: sudo apt install openocd");
  const std::string dfu_hint =
      "no STM32 in DFU mode found (0483:df11) — hold BOOT0 high (on the STM32F4DISCOVERY: a jumper from BOOT0 to "
      "VDD), press RESET, and run hmp flash again";
  EXPECT_EQ(flash::no_board_message(flash::Method::dfu, ""), dfu_hint);
  // USB could not be looked at (libusb_init failed, e.g. in a container): the same hint, and why.
  const std::string no_usb = flash::no_board_message(flash::Method::dfu, "libusb: Other error");
  EXPECT_EQ(no_usb.rfind(dfu_hint, 0), 0u) << no_usb;
  EXPECT_NE(no_usb.find("libusb: Other error"), std::string::npos);
  const std::string stlink_hint =
      "no ST-LINK probe found — connect the board's ST-LINK USB port (CN1 on the STM32F4DISCOVERY)";
  EXPECT_EQ(flash::no_board_message(flash::Method::stlink, ""), stlink_hint);
  EXPECT_EQ(flash::no_board_message(flash::Method::openocd, ""), stlink_hint);
  for (const std::string& m :
       {flash::no_board_message(flash::Method::dfu, "x"), flash::missing_tool_message(flash::Method::dfu)}) {
    EXPECT_EQ(m.find('\n'), std::string::npos);
  }
}

TEST(UdevRule, CompiledInCopyIsTheFile) {
  std::ifstream in(std::string(HMP_REPO_DIR) + "/host/flash/70-hmp.rules");
  ASSERT_TRUE(in.good());
  std::stringstream file;
  file << in.rdbuf();
  EXPECT_EQ(file.str(), flash::kUdevRule);
  EXPECT_STREQ(flash::kUdevRulePath, "/etc/udev/rules.d/70-hmp.rules");
}

// Every rule (each line that is not a comment or blank) matches one VID:PID and tags it uaccess; together they
// cover our device (hidraw and usb), the DFU bootloader and every ST-LINK id usb_scan looks for.
TEST(UdevRule, EachLineGrantsUaccessToOneId) {
  std::istringstream rules(flash::kUdevRule);
  const std::regex rule(
      R"re(SUBSYSTEM=="(usb|hidraw)", )re"
      R"re(ATTRS\{idVendor\}=="([0-9a-f]{4})", ATTRS\{idProduct\}=="([0-9a-f]{4})", TAG\+="uaccess")re");
  std::set<std::string> usb, hidraw;
  std::string line;
  int n = 0;
  while (std::getline(rules, line)) {
    if (line.empty() || line[0] == '#') continue;
    ++n;
    std::smatch m;
    ASSERT_TRUE(std::regex_match(line, m, rule)) << line;
    (m[1] == "usb" ? usb : hidraw).insert(m[2].str() + ":" + m[3].str());
  }
  EXPECT_GT(n, 0);
  EXPECT_EQ(hidraw, (std::set<std::string>{"1209:0001"}));
  std::set<std::string> want{"1209:0001"};
  for (const transport::UsbId& id : transport::kKnownIds) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "%04x:%04x", id.vid, id.pid);
    want.insert(buf);
  }
  for (const char* id : {"0483:df11", "0483:3748", "0483:374b", "0483:374a", "0483:3752", "0483:374e", "0483:374f",
                         "0483:3753", "0483:3754"}) {
    EXPECT_TRUE(want.count(id)) << id << " is not in usb_scan's list";
  }
  EXPECT_EQ(usb, want);
}

}  // namespace
