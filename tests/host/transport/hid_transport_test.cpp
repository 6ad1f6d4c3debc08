// HID transport without a device (CI machines have none): enumeration returns a list (empty here, and
// never a foreign interface), opening reports the documented one-line errors, ids parse and print.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "host/common/error.hpp"
#include "host/transport/hid_transport.hpp"
#include "host/transport/usb_backend.hpp"

namespace {

using hmp::transport::HidId;
using hmp::transport::open_hid;
using hmp::transport::open_hid_path;
using hmp::transport::TransportError;

TEST(TransportHid, EnumerationWithoutADeviceIsEmptyNotAnError) {
  // hidapi is in the usb module: without it every list would be empty and this test would prove nothing.
  std::string why;
  ASSERT_NE(hmp::transport::usb_backend(&why), nullptr) << why;
  std::vector<hmp::transport::HidDeviceInfo> found;
  ASSERT_NO_THROW(found = hmp::transport::enumerate_hid());
  for (const auto& d : found) {  // on a machine that does have one: only the protocol's interface
    EXPECT_EQ(d.usage_page, hmp::protocol::kUsagePage);
    EXPECT_EQ(d.id, HidId{});
  }
  // Any VID:PID, twice (hid_init must be idempotent).
  EXPECT_NO_THROW(hmp::transport::enumerate_hid(HidId{0xFFFF, 0xFFFE}));
  EXPECT_NO_THROW(hmp::transport::enumerate_hid(HidId{0xFFFF, 0xFFFE}));
}

TEST(TransportHid, OpeningAMissingDeviceSaysWhichOne) {
  const HidId id{0xFFFF, 0xFFFE};  // reserved-looking id no real device uses
  try {
    open_hid(id);
    FAIL() << "no exception";
  } catch (const TransportError& e) {
    EXPECT_STREQ(e.what(), "no HID device ffff:fffe found");
  }
  if (hmp::transport::enumerate_hid().empty()) {
    try {
      open_hid();
      FAIL() << "no exception";
    } catch (const TransportError& e) {
      EXPECT_STREQ(e.what(), "no HID device 1209:0001 found");
    }
  }
  EXPECT_THROW(open_hid_path("/nonexistent/hidraw9"), TransportError);
}

// What a user without the udev rule sees. Root can open any node, so as root (CI) the open runs in a child
// that has dropped to the unprivileged "nobody" ids first: the test runs everywhere instead of skipping.
TEST(TransportHid, UnreadableNodeNamesTheUdevRule) {
  // The usb module is loaded here, before the child drops its privileges: a user runs hmp from files they
  // can read, which "nobody" cannot always do in a build tree (a fresh machine's clone, for one).
  std::string why;
  ASSERT_NE(hmp::transport::usb_backend(&why), nullptr) << why;
  const auto path = std::filesystem::temp_directory_path() / ("hmp-hidraw-" + std::to_string(::getpid()));
  std::ofstream(path).put('x');
  std::filesystem::permissions(path, std::filesystem::perms::none);
  int out[2];
  ASSERT_EQ(::pipe(out), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::close(out[0]);
    constexpr uid_t kNobody = 65534;
    if (::geteuid() == 0 &&
        (::setresgid(kNobody, kNobody, kNobody) != 0 || ::setresuid(kNobody, kNobody, kNobody) != 0)) {
      _exit(3);
    }
    std::string said = "no exception";
    try {
      open_hid_path(path.string());
    } catch (const TransportError& e) {
      said = e.what();
    }
    const bool written = ::write(out[1], said.data(), said.size()) == static_cast<ssize_t>(said.size());
    _exit(written ? 0 : 4);
  }
  ::close(out[1]);
  std::string said;
  char buffer[256];
  for (ssize_t n; (n = ::read(out[0], buffer, sizeof buffer)) > 0;) said.append(buffer, static_cast<std::size_t>(n));
  ::close(out[0]);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  std::filesystem::remove(path);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "child status " << status;
  EXPECT_EQ(said, "permission denied on " + path.string() + ": install the udev rule (hmp flash --install-udev-rule)");
}

// hidapi's hidraw backend crashes on a node that is not hidraw's: a regular file, a folder or another
// device is refused first, with the path named, and a file is left as it was.
TEST(TransportHid, APathThatIsNotAHidrawNodeIsRefused) {
  const auto path = std::filesystem::temp_directory_path() / ("hmp-not-hidraw-" + std::to_string(::getpid()));
  std::ofstream(path) << "MThd precious";
  for (const std::string& p : {path.string(), std::string("/dev/null"), path.parent_path().string()}) {
    try {
      open_hid_path(p);
      ADD_FAILURE() << p << ": no exception";
    } catch (const hmp::BadInput& e) {
      EXPECT_NE(std::string(e.what()).find("HID device " + p + ": "), std::string::npos) << e.what();
    }
  }
  std::ifstream in(path);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "MThd precious");
  std::filesystem::remove(path);
}

TEST(TransportHid, IdsParseAndPrint) {
  EXPECT_EQ(hmp::transport::parse_hid_id("1209:0001"), HidId{});
  EXPECT_EQ(hmp::transport::parse_hid_id("0x1209:0xBEEF"), (HidId{0x1209, 0xBEEF}));
  EXPECT_EQ(hmp::transport::parse_hid_id("ffff:0"), (HidId{0xFFFF, 0}));
  EXPECT_EQ(hmp::transport::to_string(HidId{0xABCD, 0x0042}), "abcd:0042");
  for (const char* bad : {"", "1209", "1209:", ":0001", "12345:0001", "1209:000g", "1209:0001:2", "-1:1"}) {
    EXPECT_THROW(hmp::transport::parse_hid_id(bad), hmp::BadInput) << bad;
  }
}

}  // namespace
