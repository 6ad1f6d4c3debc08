// Writing a file the user named (host/output/output_file.hpp): an existing file is kept without --force
// and replaced with it; the writing goes to PATH.part, renamed into place when whole, so a failed or
// interrupted write leaves the user's name as it was and no .part behind; a missing folder is refused
// before any writing.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "host/common/error.hpp"
#include "host/output/output_file.hpp"
#include "host/output/bar_chart.hpp"

namespace {

namespace fs = std::filesystem;
using namespace hmp::output;

class OutputFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hmp_output_file_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

std::string text_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string error_of(const std::string& path, bool force) {
  try {
    FilePtr f = open_for_writing(path, force);
    std::fputs("new", f.get());
    close_output(f);
  } catch (const hmp::BadInput& e) {
    return e.what();
  }
  return "";
}

TEST_F(OutputFileTest, ANewFileIsWrittenThroughPart) {
  const std::string p = path("a.csv");
  FilePtr f = open_for_writing(p, false);
  std::fputs("half", f.get());
  std::fflush(f.get());
  EXPECT_FALSE(fs::exists(p)) << "written under the user's name before it was whole";
  EXPECT_TRUE(fs::exists(part_path(p)));
  close_output(f);
  EXPECT_EQ(text_of(p), "half");
  EXPECT_FALSE(fs::exists(part_path(p)));
}

TEST_F(OutputFileTest, AnExistingFileIsKeptWithoutForceReplacedWithIt) {
  const std::string p = path("a.csv");
  std::ofstream(p) << "old";
  // No terminal in a test run: nobody is asked, the file is refused.
  EXPECT_EQ(error_of(p, false), p + ": file exists (use --force to overwrite)");
  EXPECT_EQ(text_of(p), "old");
  EXPECT_FALSE(fs::exists(part_path(p)));
  EXPECT_EQ(error_of(p, true), "");
  EXPECT_EQ(text_of(p), "new");
  EXPECT_FALSE(fs::exists(part_path(p)));
}

TEST_F(OutputFileTest, AWriteCutShortLeavesTheOldFileAndNoPart) {
  const std::string p = path("a.csv");
  std::ofstream(p) << "old";
  try {
    FilePtr f = open_for_writing(p, true);
    std::fputs("half", f.get());
    throw std::runtime_error("interrupted");  // the file closes on the way out: not renamed
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(text_of(p), "old");
  EXPECT_FALSE(fs::exists(part_path(p)));
  {
    // Closed on the normal path without close_output (as a caller that forgets it): still renamed.
    FilePtr f = open_for_writing(p, true);
    std::fputs("whole", f.get());
  }
  EXPECT_EQ(text_of(p), "whole");
  EXPECT_FALSE(fs::exists(part_path(p)));
}

TEST_F(OutputFileTest, StagedOutputCommitsOrRemovesItsPart) {
  const std::string p = path("fig.png");
  std::ofstream(p) << "old";
  {
    StagedOutput staged(p);
    EXPECT_EQ(staged.part(), p + ".part");
    std::ofstream(staged.part()) << "half";
  }  // not committed: a writer failed
  EXPECT_EQ(text_of(p), "old");
  EXPECT_FALSE(fs::exists(p + ".part"));
  {
    StagedOutput staged(p);
    std::ofstream(staged.part()) << "new";
    staged.commit();
  }
  EXPECT_EQ(text_of(p), "new");
  EXPECT_FALSE(fs::exists(p + ".part"));
}

// PATH.part already there, as a file or as a link to one: kept (and the link's target untouched) without
// --force; with it, replaced by a file of our own, never written through. Created under a writer's feet,
// it stops the writer and is left as it is.
TEST_F(OutputFileTest, APartAlreadyThereIsNeitherTakenOverNorWrittenThrough) {
  const std::string p = path("a.csv"), victim = path("victim.txt");
  std::ofstream(victim) << "victim";
  std::ofstream(part_path(p)) << "precious";
  EXPECT_EQ(error_of(p, false), part_path(p) + ": exists, the temporary name of " + p + " (use --force to replace it)");
  EXPECT_EQ(text_of(part_path(p)), "precious");
  fs::remove(part_path(p));
  fs::create_symlink(victim, part_path(p));
  EXPECT_NE(error_of(p, false), "");
  EXPECT_TRUE(fs::is_symlink(part_path(p)));
  EXPECT_EQ(error_of(p, true), "");
  EXPECT_EQ(text_of(victim), "victim");
  EXPECT_EQ(text_of(p), "new");
  EXPECT_FALSE(fs::is_symlink(p));
  EXPECT_FALSE(fs::exists(fs::symlink_status(part_path(p))));

  const std::string q = path("fig.png");
  check_writable(q, false);
  fs::create_symlink(victim, part_path(q));  // between the check and the writing
  EXPECT_THROW(StagedOutput staged(q), hmp::BadInput);
  EXPECT_TRUE(fs::is_symlink(part_path(q)));
  EXPECT_EQ(text_of(victim), "victim");
  fs::remove(part_path(q));
  fs::create_directory(part_path(q));
  EXPECT_EQ(error_of(q, true), part_path(q) + ": is a directory, the temporary name of " + q);
  EXPECT_TRUE(fs::is_directory(part_path(q)));
}

TEST_F(OutputFileTest, BadNamesAreRefusedBeforeAnyWriting) {
  EXPECT_EQ(error_of(path("no/such/folder/a.csv"), true),
            path("no/such/folder/a.csv") + ": folder " + path("no/such/folder") + " does not exist");
  EXPECT_FALSE(fs::exists(path("no")));
  EXPECT_EQ(error_of(dir_.string(), true), dir_.string() + ": is a directory");
}

TEST_F(OutputFileTest, TheBarChartKeepsAnExistingFile) {
  const std::string p = path("fig.png");
  std::ofstream(p) << "old";
  try {
    hmp::output::write_bar_chart_png(p, {}, {}, false);
    FAIL() << "an existing figure was replaced without --force";
  } catch (const hmp::BadInput& e) {
    EXPECT_EQ(std::string(e.what()), p + ": file exists (use --force to overwrite)");
  }
  EXPECT_EQ(text_of(p), "old");
}

}  // namespace
