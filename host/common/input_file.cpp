#include "host/common/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "host/common/error.hpp"
#include "host/common/printable.hpp"

namespace hmp {

InputFile::InputFile(const std::string& path) : path_(path) {
  // O_NONBLOCK so that a FIFO is refused as "not a regular file" instead of blocking the open; it
  // changes nothing for regular files.
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd_ < 0) {
    const int err = errno;
    if (err == ENOENT || err == ENOTDIR) throw BadInput(shown() + ": no such file");
    if (err == EISDIR) throw BadInput(shown() + ": is a directory");
    throw BadInput(shown() + ": cannot open (" + std::strerror(err) + ")");
  }
  struct stat info {};
  if (::fstat(fd_, &info) != 0) {
    const int err = errno;
    ::close(fd_);
    throw BadInput(shown() + ": cannot read (" + std::strerror(err) + ")");
  }
  if (!S_ISREG(info.st_mode)) {
    ::close(fd_);
    throw BadInput(shown() + (S_ISDIR(info.st_mode) ? ": is a directory" : ": not a regular file"));
  }
  size_ = static_cast<std::uint64_t>(info.st_size);
}

InputFile::~InputFile() { ::close(fd_); }

std::string InputFile::shown() const { return printable(path_); }

void InputFile::read_all(std::uint8_t* out) const {
  const auto length = static_cast<std::size_t>(size_);
  std::size_t got = 0;
  while (got < length) {
    const ::ssize_t n = ::read(fd_, out + got, length - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw BadInput(shown() + ": cannot read (" + std::strerror(errno) + ")");
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  if (got != length) throw BadInput(shown() + ": cannot read (it shrank while being read)");
}

std::string read_input_file(const std::string& path, std::uint64_t max_bytes) {
  const InputFile file(path);
  if (file.size() > max_bytes) throw BadInput(file.shown() + ": larger than " + std::to_string(max_bytes) + " bytes");
  std::string text(static_cast<std::size_t>(file.size()), '\0');
  file.read_all(reinterpret_cast<std::uint8_t*>(text.data()));
  return text;
}

void check_input_file(const std::string& path) { const InputFile file(path); }

}  // namespace hmp
