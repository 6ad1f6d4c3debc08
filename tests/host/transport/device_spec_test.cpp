// `--device` parsing (design §3) and what `hmp devices` prints without a device.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "host/common/error.hpp"
#include "host/transport/device_spec.hpp"
#include "host/transport/sim_transport.hpp"

namespace {

using hmp::transport::DeviceSpec;
using hmp::transport::parse_device_spec;
using Kind = DeviceSpec::Kind;

TEST(TransportDeviceSpec, ParsesEveryForm) {
  EXPECT_EQ(parse_device_spec("auto").kind, Kind::automatic);
  EXPECT_EQ(parse_device_spec("sim").kind, Kind::sim);
  EXPECT_EQ(parse_device_spec("qemu").kind, Kind::qemu);
  EXPECT_FALSE(parse_device_spec("qemu").qemu_net);
  EXPECT_EQ(parse_device_spec("qemu:net").kind, Kind::qemu);
  EXPECT_TRUE(parse_device_spec("qemu:net").qemu_net);
  EXPECT_EQ(parse_device_spec("hid").kind, Kind::hid);
  EXPECT_EQ(parse_device_spec("hid").hid, hmp::transport::HidId{});
  const DeviceSpec h = parse_device_spec("hid:16c0:05df");
  EXPECT_EQ(h.kind, Kind::hid);
  EXPECT_EQ(h.hid, (hmp::transport::HidId{0x16c0, 0x05df}));
  EXPECT_EQ(parse_device_spec("hid:/dev/hidraw3").path, "/dev/hidraw3");
  const DeviceSpec s = parse_device_spec("serial:/dev/pts/4");
  EXPECT_EQ(s.kind, Kind::serial);
  EXPECT_EQ(s.path, "/dev/pts/4");
  EXPECT_EQ(s.baud, 0u);
  const DeviceSpec b = parse_device_spec("serial:/dev/ttyACM0@921600");
  EXPECT_EQ(b.path, "/dev/ttyACM0");
  EXPECT_EQ(b.baud, 921600u);
  EXPECT_EQ(parse_device_spec("serial:/tmp/a@b/uart").path, "/tmp/a@b/uart");  // '@' not followed by digits
  for (const char* text : {"auto", "sim", "qemu", "qemu:net", "hid:1209:0001", "hid:/dev/hidraw0", "serial:/dev/pts/4",
                           "serial:/dev/ttyUSB0@115200"}) {
    EXPECT_EQ(hmp::transport::to_string(parse_device_spec(text)), text);
  }
}

TEST(TransportDeviceSpec, RejectsWithTheTextInTheMessage) {
  for (const char* text : {"", "usb", "qemu:", "qemu:uart", "qemu:net:x", "hid:", "hid:zz:01",
                           "serial:", "serial:@9600", "serial:/dev/x@0", "SIM"}) {
    try {
      parse_device_spec(text);
      ADD_FAILURE() << "accepted '" << text << "'";
    } catch (const hmp::BadInput& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("'") + text + "'"), std::string::npos) << e.what();
    }
  }
}

TEST(TransportDeviceSpec, OpensTheSimulatedDevice) {
  auto opened = hmp::transport::open_device(parse_device_spec("sim"));
  ASSERT_TRUE(opened.transport);
  EXPECT_EQ(opened.transport->name(), "sim");
  EXPECT_TRUE(opened.note.empty());
  if (hmp::transport::enumerate_hid().empty()) {
    auto fallback = hmp::transport::open_device(parse_device_spec("auto"));
    EXPECT_EQ(fallback.transport->name(), "sim");
    EXPECT_NE(fallback.note.find("simulated device"), std::string::npos);
  }
}

std::string run(const std::string& args, int* rc) {
  const std::string cmd = std::string(HMP_BIN_DIR) + "/hmp " + args + " 2>&1";
  std::FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  char buf[512];
  while (p && std::fgets(buf, sizeof buf, p)) out += buf;
  const int status = p ? pclose(p) : -1;
  *rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

TEST(TransportDeviceSpec, DevicesCommandWithoutADevice) {
  if (!hmp::transport::enumerate_hid().empty()) GTEST_SKIP() << "a device is connected";
  int rc = -1;
  EXPECT_NE(run("devices", &rc).find("no HID device 1209:0001 found"), std::string::npos);
  EXPECT_EQ(rc, 0);
  const auto j = nlohmann::json::parse(run("devices --json", &rc));
  EXPECT_EQ(rc, 0);
  EXPECT_TRUE(j.at("devices").is_array());
  EXPECT_TRUE(j.at("devices").empty());
  EXPECT_EQ(j.at("id"), "1209:0001");
  run("devices --id nope", &rc);
  EXPECT_EQ(rc, 2);
}

}  // namespace
