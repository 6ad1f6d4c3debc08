#pragma once
// Files the user named for output. Never overwritten silently: an existing file is replaced only with
// --force, or after a "yes" when we can ask on a terminal. Never left half-written: the writing goes to
// PATH.part, renamed to PATH once complete, so an interrupted or failed write leaves the user's name as
// it was (the old file, or none). PATH.part is created afresh, never written through: one already there
// is replaced only as PATH would be (--force or a "yes").
#include <cstdio>
#include <memory>
#include <string>

namespace hmp::output {

// Closes a file from open_for_writing: renames its PATH.part into place when the write went well and the
// file is closed on the normal path; removes PATH.part when an exception is on its way (the write was cut
// short) or the file had an error. close_output does the same and reports failures.
struct FileCloser {
  std::string path;    // the user's name; empty for standard output
  int exceptions = 0;  // std::uncaught_exceptions() when opened
  void operator()(std::FILE* f) const;
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

// Checks that `path` may be written (throws BadInput otherwise): not a directory, its folder exists, and
// an existing file, or PATH.part, only with `force` (or a "yes"; PATH.part is then removed). "-" means
// standard output. Call it before any work.
void check_writable(const std::string& path, bool force);
// check_writable + fopen of PATH.part in binary mode. "-" returns stdout.
FilePtr open_for_writing(const std::string& path, bool force);
// Flushes and closes `f`, then renames PATH.part to PATH; throws (and removes PATH.part) when the write
// or the rename failed. For stdout: flushes and checks for errors.
void close_output(FilePtr& f);

// PATH.part: where the writing of PATH goes.
std::string part_path(const std::string& path);

// For writers that take a path (cairo, libsndfile, ffmpeg): they write part(), commit() renames it to
// path(). Not committed (an exception, an error), the destructor removes part(). The path must have
// passed check_writable. The constructor creates part() (BadInput if something is there by then).
class StagedOutput {
 public:
  explicit StagedOutput(std::string path);
  ~StagedOutput();
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;

  const std::string& path() const { return path_; }
  const std::string& part() const { return part_; }
  void commit();  // throws std::runtime_error when the rename fails

 private:
  std::string path_, part_;
  bool committed_ = false;
};

// Lower-case extension without the dot ("csv", "wav", "png"), or "" if none.
std::string extension_of(const std::string& path);

}  // namespace hmp::output
