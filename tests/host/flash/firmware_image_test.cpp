// host/flash/firmware_image: the default stm32f407 image is stale when it is missing or older than any file
// under firmware/, shared/ or boards/stm32f407/ of the source tree, and only then (a newer file elsewhere —
// host/, another board — does not count).
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "host/common/install_layout.hpp"
#include "host/flash/firmware_image.hpp"

namespace {

namespace fs = std::filesystem;
namespace flash = hmp::flash;

class FlashImage : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string tmpl = (fs::temp_directory_path() / "hmp-flash-image-XXXXXX").string();
    ASSERT_NE(::mkdtemp(tmpl.data()), nullptr);
    root_ = tmpl;
  }
  void TearDown() override { fs::remove_all(root_); }

  // Writes root/rel with a modification time `age` before now.
  fs::path write(const std::string& rel, std::chrono::seconds age) {
    const fs::path p = root_ / rel;
    fs::create_directories(p.parent_path());
    std::ofstream(p) << rel;
    fs::last_write_time(p, fs::file_time_type::clock::now() - age);
    return p;
  }

  fs::path root_;
};

TEST_F(FlashImage, DefaultPaths) {
  const std::string version = hmp::install::version_text();
  EXPECT_EQ(flash::default_image("/src", true),
            fs::path("/src/build/stm32f407/boards/stm32f407/hmp_fw_stm32f407-" + version + ".elf"));
  EXPECT_EQ(flash::default_image("/src", false),
            fs::path("/src/build/stm32f407/boards/stm32f407/hmp_fw_stm32f407-" + version + ".bin"));
  EXPECT_FALSE(flash::build_configured(root_));
  write("build/stm32f407/CMakeCache.txt", std::chrono::seconds(0));
  EXPECT_TRUE(flash::build_configured(root_));
}

TEST_F(FlashImage, MissingIsStale) {
  write("firmware/core.cpp", std::chrono::hours(2));
  const flash::Freshness f = flash::image_freshness(flash::default_image(root_, false), root_);
  EXPECT_TRUE(f.stale);
  EXPECT_EQ(f.why, "it does not exist");
}

TEST_F(FlashImage, NewerThanEverySourceIsFresh) {
  using std::chrono::hours;
  for (const char* rel : {"firmware/core.cpp", "shared/protocol.hpp", "boards/stm32f407/main.cpp"})
    write(rel, hours(3));
  write("host/cli/main.cpp", hours(0));           // not what the image is built from
  write("boards/qemu-an386/main.cpp", hours(0));  // another board
  const fs::path image = write("build/stm32f407/boards/stm32f407/hmp_fw_stm32f407.bin", hours(1));
  const flash::Freshness f = flash::image_freshness(image, root_);
  EXPECT_FALSE(f.stale) << f.why;
  EXPECT_EQ(f.why, "");
}

TEST_F(FlashImage, OlderThanAnySourceIsStale) {
  using std::chrono::hours;
  for (const char* changed :
       {"firmware/sub/dir/voice.hpp", "shared/protocol.hpp", "boards/stm32f407/pins.hpp",
        "boards/stm32f407/stm32f407.ld", "boards/cortex-m/serial_link.hpp", "firmware/CMakeLists.txt"}) {
    SCOPED_TRACE(changed);
    fs::remove_all(root_ / "firmware");
    fs::remove_all(root_ / "shared");
    fs::remove_all(root_ / "boards");
    for (const char* rel : {"firmware/core.cpp", "shared/framing.hpp", "boards/stm32f407/main.cpp"})
      write(rel, hours(3));
    const fs::path image = write("build/stm32f407/boards/stm32f407/hmp_fw_stm32f407.elf", hours(2));
    write(changed, hours(1));
    const flash::Freshness f = flash::image_freshness(image, root_);
    EXPECT_TRUE(f.stale);
    EXPECT_EQ(f.why, std::string("it is older than ") + changed);
  }
}

// Files that are not build inputs (documentation, scripts run by tests) do not make the image stale.
TEST_F(FlashImage, EditedDocumentationIsNotAStaleImage) {
  using std::chrono::hours;
  write("firmware/core.cpp", hours(3));
  const fs::path image = write("build/stm32f407/boards/stm32f407/hmp_fw_stm32f407.bin", hours(2));
  write("boards/stm32f407/README.md", hours(1));
  write("boards/stm32f407/check_image.sh", hours(1));
  const flash::Freshness f = flash::image_freshness(image, root_);
  EXPECT_FALSE(f.stale) << f.why;
}

TEST_F(FlashImage, NoSourceFoldersIsFresh) {
  const fs::path image = write("fw.bin", std::chrono::seconds(0));
  EXPECT_FALSE(flash::image_freshness(image, root_).stale);
}

}  // namespace
