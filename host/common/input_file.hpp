#pragma once
// Files the user named for reading (the song, --config, --soundfont, study results): opened here so that
// every reader refuses the same things with the same one-line BadInput naming the path — "PATH: is a
// directory", "PATH: no such file", "PATH: not a regular file" (a FIFO or a device), "PATH: cannot read …".
#include <cstdint>
#include <string>

namespace hmp {

class InputFile {
 public:
  explicit InputFile(const std::string& path);  // a regular file, open for reading, or BadInput
  ~InputFile();
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  std::uint64_t size() const { return size_; }
  // Reads the whole file, size() bytes, into `out`; BadInput on a read error or when it shrank meanwhile.
  void read_all(std::uint8_t* out) const;
  // The path as messages show it (escaped with printable()).
  std::string shown() const;

 private:
  std::string path_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

// The whole file as bytes; BadInput as InputFile's, or "PATH: larger than N bytes".
std::string read_input_file(const std::string& path, std::uint64_t max_bytes = std::uint64_t{1} << 30);

// InputFile's checks alone, for a library that opens the path itself (FluidSynth's SoundFont loader).
void check_input_file(const std::string& path);

}  // namespace hmp
