// host/flash: the flashing tools' command lines as their documentation and boards/stm32f407/README.md
// give them (dfu-util(1): -d VID:PID, -a alt, -s address[:leave], -D file; st-flash: [--reset] write
// FILE ADDR; OpenOCD's `program FILE verify reset exit`), shell quoting that survives a shell, and the
// USB ids hmp looks for.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "host/flash/flash_plan.hpp"
#include "host/flash/usb_scan.hpp"

namespace {

namespace flash = hmp::flash;
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
  for (const char* bad : {"", "DFU", "st-link", "jtag", "dfu "}) EXPECT_FALSE(flash::parse_method(bad).has_value()) << bad;
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
  const flash::UsbId* dfu = flash::known_id(0x0483, 0xdf11);
  ASSERT_NE(dfu, nullptr);
  EXPECT_EQ(dfu->kind, flash::ProbeKind::stm32_dfu);
  ASSERT_NE(flash::known_id(0x0483, 0x3748), nullptr);
  EXPECT_EQ(flash::known_id(0x0483, 0x3748)->kind, flash::ProbeKind::stlink);
  EXPECT_EQ(flash::known_id(0x1209, 0x0001), nullptr) << "our own device is HID, listed by hidapi";
  EXPECT_EQ(flash::known_id(0x0483, 0x5740), nullptr);
  const flash::FoundProbe p{flash::ProbeKind::stm32_dfu, "STM32 in DFU mode", 1, 5};
  EXPECT_EQ(flash::describe(p), "STM32 in DFU mode on bus 1 device 5 — run hmp flash");
}

}  // namespace
