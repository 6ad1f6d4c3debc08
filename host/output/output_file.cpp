#include "host/output/output_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <vector>

#include "host/common/error.hpp"
#include "host/common/printable.hpp"

namespace hmp::output {

namespace fs = std::filesystem;

namespace {
// Paths the user agreed to overwrite in this run: a writer checks its path before its work and again
// when it opens the file, and the question is asked once.
std::vector<std::string>& confirmed_paths() {
  static std::vector<std::string> paths;
  return paths;
}

bool ask_yes(const std::string& path, const std::string& question) {
  auto& confirmed = confirmed_paths();
  if (std::find(confirmed.begin(), confirmed.end(), path) != confirmed.end()) return true;
  if (!isatty(STDIN_FILENO) || !isatty(STDERR_FILENO)) return false;
  std::cerr << question << " [y/N] " << std::flush;
  std::string answer;
  if (!std::getline(std::cin, answer)) return false;
  const bool yes = !answer.empty() && (answer[0] == 'y' || answer[0] == 'Y');
  if (yes) confirmed.push_back(path);
  return yes;
}

// Renames PATH.part to PATH; "" or what went wrong (PATH.part is removed then).
std::string rename_into_place(const std::string& path) {
  const std::string part = part_path(path);
  std::error_code ec;
  fs::rename(part, path, ec);
  if (!ec) return {};
  std::error_code ignored;
  fs::remove(part, ignored);
  return printable(path) + ": cannot rename " + printable(part) + " into place (" + ec.message() + ")";
}

void remove_part(const std::string& path) {
  std::error_code ignored;
  fs::remove(part_path(path), ignored);
}

// Creates PATH.part, only if nothing is there: neither a file of that name (the user's, or another run's)
// nor a link (it would be written through) is taken over. Returns its descriptor.
int create_part(const std::string& path) {
  const std::string part = part_path(path);
  const int fd = ::open(part.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd >= 0) return fd;
  if (errno == EEXIST) throw BadInput(printable(part) + ": exists; it is not overwritten (--force replaces it)");
  throw BadInput(printable(part) + ": cannot open for writing (" + std::strerror(errno) + ")");
}

// A PATH.part already there (a write cut short by a crash or a power cut, or a file of the user's) is
// replaced only with `force` or a "yes", like PATH itself; a folder never.
void check_part(const std::string& path, bool force) {
  const fs::path part(part_path(path));
  const std::string shown = printable(part.string());
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(part, ec);
  if (!fs::exists(status)) return;
  if (fs::is_directory(status)) throw BadInput(shown + ": is a directory, the temporary name of " + printable(path));
  if (!force && !ask_yes(part.string(), shown + " exists (a write cut short?). Replace it?")) {
    throw BadInput(shown + ": exists, the temporary name of " + printable(path) + " (use --force to replace it)");
  }
  if (!fs::remove(part, ec)) throw BadInput(shown + ": cannot remove (" + ec.message() + ")");
}
}  // namespace

std::string part_path(const std::string& path) { return path + ".part"; }

std::string extension_of(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  std::string lower = ext.empty() ? "" : ext.substr(1);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return lower;
}

void check_writable(const std::string& path, bool force) {
  if (path == "-") return;
  std::error_code ec;
  const fs::path p(path);
  const std::string shown = printable(path);
  if (fs::is_directory(p, ec)) throw BadInput(shown + ": is a directory");
  const fs::path parent = p.has_parent_path() ? p.parent_path() : fs::path(".");
  if (!fs::is_directory(parent, ec))
    throw BadInput(shown + ": folder " + printable(parent.string()) + " does not exist");
  if (fs::exists(p, ec) && !force && !ask_yes(path, shown + " exists. Overwrite?")) {
    throw BadInput(shown + ": file exists (use --force to overwrite)");
  }
  check_part(path, force);
}

void FileCloser::operator()(std::FILE* f) const {
  if (f == nullptr || f == stdout) return;
  const bool written = !std::ferror(f);
  const bool closed = std::fclose(f) == 0;
  if (path.empty()) return;
  if (written && closed && std::uncaught_exceptions() <= exceptions) {
    (void)rename_into_place(path);  // a destructor cannot report; close_output is the reporting way
  } else {
    remove_part(path);
  }
}

FilePtr open_for_writing(const std::string& path, bool force) {
  if (path == "-") return FilePtr(stdout);
  check_writable(path, force);
  const int fd = create_part(path);
  std::FILE* f = ::fdopen(fd, "wb");
  if (!f) {
    const int err = errno;
    ::close(fd);
    remove_part(path);
    throw BadInput(printable(part_path(path)) + ": cannot open for writing (" + std::strerror(err) + ")");
  }
  return FilePtr(f, FileCloser{path, std::uncaught_exceptions()});
}

void close_output(FilePtr& f) {
  if (!f) return;
  if (f.get() == stdout) {
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) throw std::runtime_error("standard output: write failed");
    return;
  }
  const std::string path = f.get_deleter().path;
  std::FILE* file = f.release();
  const bool written = !std::ferror(file);
  const bool closed = std::fclose(file) == 0;
  if (!written || !closed) {
    remove_part(path);
    throw std::runtime_error(printable(path) + ": write failed (disk full?)");
  }
  if (const std::string error = rename_into_place(path); !error.empty()) throw std::runtime_error(error);
}

StagedOutput::StagedOutput(std::string path) : path_(std::move(path)), part_(part_path(path_)) {
  ::close(create_part(path_));  // the writer opens it again by name; it is ours now
}

StagedOutput::~StagedOutput() {
  if (!committed_) remove_part(path_);
}

void StagedOutput::commit() {
  if (const std::string error = rename_into_place(path_); !error.empty()) throw std::runtime_error(error);
  committed_ = true;
}

}  // namespace hmp::output
