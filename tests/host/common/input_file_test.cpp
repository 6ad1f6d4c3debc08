// Reading a file the user named (host/common/input_file.hpp): what is not a readable regular file is
// refused with one line naming the path and what is wrong with it.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "host/common/error.hpp"
#include "host/common/input_file.hpp"

namespace {

namespace fs = std::filesystem;

class InputFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hmp_input_file_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

std::string error_of(const std::string& path) {
  try {
    (void)hmp::read_input_file(path);
  } catch (const hmp::BadInput& e) {
    return e.what();
  }
  return "(no error)";
}

TEST_F(InputFileTest, ReadsARegularFileWhole) {
  std::ofstream(path("a.txt"), std::ios::binary) << std::string("x\0y\n", 4);
  EXPECT_EQ(hmp::read_input_file(path("a.txt")), std::string("x\0y\n", 4));
  std::ofstream(path("empty.txt")).flush();
  EXPECT_EQ(hmp::read_input_file(path("empty.txt")), "");
}

TEST_F(InputFileTest, ADirectoryIsNamedAsOne) {
  EXPECT_EQ(error_of(dir_.string()), dir_.string() + ": is a directory");
  try {
    hmp::check_input_file(dir_.string());
    FAIL() << "a directory passed";
  } catch (const hmp::BadInput& e) {
    EXPECT_EQ(std::string(e.what()), dir_.string() + ": is a directory");
  }
}

TEST_F(InputFileTest, MissingFifoAndTooLarge) {
  EXPECT_EQ(error_of(path("missing.csv")), path("missing.csv") + ": no such file");
  EXPECT_EQ(error_of(path("missing/below.csv")), path("missing/below.csv") + ": no such file");
  ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0600), 0);
  EXPECT_EQ(error_of(path("fifo")), path("fifo") + ": not a regular file");  // refused, not waited on
  std::ofstream(path("big.txt")) << "0123456789";
  try {
    (void)hmp::read_input_file(path("big.txt"), 4);
    FAIL() << "no size limit";
  } catch (const hmp::BadInput& e) {
    EXPECT_EQ(std::string(e.what()), path("big.txt") + ": larger than 4 bytes");
  }
}

TEST_F(InputFileTest, ThePathIsShownEscaped) {
  const std::string odd = path(std::string("bad\xFFname\nx"));
  fs::create_directories(odd);
  EXPECT_EQ(error_of(odd), path("bad\\xFFname\\nx") + ": is a directory");
}

}  // namespace
