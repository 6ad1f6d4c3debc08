// config::with_peak_force: [device] peak_force_n set, every other byte of the file kept.
#include <gtest/gtest.h>

#include "host/common/error.hpp"
#include "host/config/config_edit.hpp"

namespace {

TEST(ConfigEdit, PeakForceKeepsEverythingElse) {
  EXPECT_EQ(hmp::config::with_peak_force("", 2.5), "[device]\npeak_force_n = 2.5\n");
  EXPECT_EQ(hmp::config::with_peak_force("[mapping]\nmode = \"paper\"", 2.5),
            "[mapping]\nmode = \"paper\"\n\n[device]\npeak_force_n = 2.5\n");
  EXPECT_EQ(hmp::config::with_peak_force("# mine\n[device]\ntick_hz = 1000\npeak_force_n = 1.0  # old\n[gm]\n", 3),
            "# mine\n[device]\ntick_hz = 1000\npeak_force_n = 3  # old\n[gm]\n");
  EXPECT_EQ(hmp::config::with_peak_force("[device]\ntick_hz = 1000\n[gm]\n\"1\" = \"organ\"", 3),
            "[device]\npeak_force_n = 3\ntick_hz = 1000\n[gm]\n\"1\" = \"organ\"");
  EXPECT_THROW(hmp::config::with_peak_force("device.peak_force_n = 1\n", 3), hmp::BadInput);
  EXPECT_THROW(hmp::config::with_peak_force("device = { peak_force_n = 1 }\n", 3), hmp::BadInput);
}

// A byte-order mark is kept and the [device] behind it found (a second [device] table made the edited
// file one no TOML reader takes); lines written into a CRLF file end in CRLF.
TEST(ConfigEdit, PeakForceKeepsAByteOrderMarkAndCrlf) {
  const std::string bom = "\xEF\xBB\xBF";
  EXPECT_EQ(hmp::config::with_peak_force(bom + "[device]\ntick_hz = 1000\n", 3),
            bom + "[device]\npeak_force_n = 3\ntick_hz = 1000\n");
  EXPECT_EQ(hmp::config::with_peak_force(bom, 3), bom + "[device]\npeak_force_n = 3\n");
  EXPECT_EQ(hmp::config::with_peak_force("[device]\r\npeak_force_n = 1\r\n", 3), "[device]\r\npeak_force_n = 3\r\n");
  EXPECT_EQ(hmp::config::with_peak_force("[device]\r\npeak_force_n = 1", 3), "[device]\r\npeak_force_n = 3");
  EXPECT_EQ(hmp::config::with_peak_force("[mapping]\r\nmode = \"paper\"\r\n", 3),
            "[mapping]\r\nmode = \"paper\"\r\n\r\n[device]\r\npeak_force_n = 3\r\n");
}

}  // namespace
