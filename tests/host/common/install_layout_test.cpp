// host/common/install_layout: what an hmp run from this build tree finds, against facts known here: the
// version written in CMakeLists.txt's project() line, the repository this test was built from, and a
// source tree named by HMP_SOURCE_DIR.
#include "host/common/install_layout.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

namespace hmp {
namespace {

namespace fs = std::filesystem;

std::string project_version() {
  std::ifstream in(fs::path(HMP_REPO_DIR) / "CMakeLists.txt");
  const std::regex project(R"(^project\(\S+ VERSION ([0-9]+\.[0-9]+\.[0-9]+))");
  std::smatch m;
  for (std::string line; std::getline(in, line);)
    if (std::regex_search(line, m, project)) return m[1];
  return "";
}

class InstallLayout : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const char* e = std::getenv("HMP_SOURCE_DIR")) saved_ = e;
    unsetenv("HMP_SOURCE_DIR");
  }
  void TearDown() override {
    if (saved_) setenv("HMP_SOURCE_DIR", saved_->c_str(), 1);
  }
  std::optional<std::string> saved_;
};

TEST_F(InstallLayout, VersionAndImageNamesFollowTheProjectLine) {
  const std::string version = project_version();
  ASSERT_FALSE(version.empty());
  EXPECT_EQ(install::version_text(), version);
  EXPECT_EQ(install::image_file_name("qemu-an386", ".elf"), "hmp_fw_qemu_an386-" + version + ".elf");
  EXPECT_EQ(install::image_file_name("stm32f407", ".dfu"), "hmp_fw_stm32f407-" + version + ".dfu");
}

// This test runs from <build>/tests/, beside the build tree's bin/: it finds the source tree through the
// file CMake wrote, and the examples there (nothing is installed under <build>/share/hmp).
TEST_F(InstallLayout, ABuildTreeFindsItsSourceTree) {
  const auto tree = install::source_tree();
  ASSERT_TRUE(tree.has_value());
  EXPECT_TRUE(fs::equivalent(*tree, HMP_REPO_DIR));
  EXPECT_TRUE(fs::equivalent(install::example("pedal-demo.mid"), fs::path(HMP_REPO_DIR) / "examples/pedal-demo.mid"));
  EXPECT_EQ(install::data_dir(), install::program_dir().parent_path() / "share/hmp");
  EXPECT_EQ(install::installed_image("stm32f407", ".bin"),
            install::data_dir() / "firmware" / install::image_file_name("stm32f407", ".bin"));
}

TEST_F(InstallLayout, TheEnvironmentNamesAnotherTree) {
  setenv("HMP_SOURCE_DIR", "/some/other tree", 1);
  EXPECT_EQ(install::source_tree(), fs::path("/some/other tree"));
  // An example missing from both places: the installed path, which the caller reports as missing.
  EXPECT_EQ(install::example("pedal-demo.mid"), install::data_dir() / "examples/pedal-demo.mid");
  setenv("HMP_SOURCE_DIR", "", 1);  // empty: not set
  EXPECT_TRUE(fs::equivalent(*install::source_tree(), HMP_REPO_DIR));
}

}  // namespace
}  // namespace hmp
