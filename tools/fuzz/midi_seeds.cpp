// Writes the seed corpus of fuzz_midi: every .mid file of the development corpus (tests/data/midi,
// design §4) plus a few tiny hand-made files for the container and event paths those may not reach in few
// bytes (format 0 with running status, format 2, SMPTE division, RIFF RMID, sysex, odd header lengths).
// Small seeds matter: libFuzzer mutates them many times faster than the 50 KB real songs.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "seed_file.hpp"

namespace fs = std::filesystem;
using Bytes = std::vector<unsigned char>;

namespace {

Bytes chunk(const char* id, const Bytes& body) {
  Bytes b(id, id + 4);
  const auto n = static_cast<unsigned>(body.size());
  for (int shift = 24; shift >= 0; shift -= 8) b.push_back(static_cast<unsigned char>(n >> shift));
  b.insert(b.end(), body.begin(), body.end());
  return b;
}

// MThd + the given track bodies.
Bytes smf(unsigned format, unsigned char division_hi, unsigned char division_lo, const std::vector<Bytes>& tracks) {
  const auto n = static_cast<unsigned char>(tracks.size());
  Bytes file = chunk("MThd", {0, static_cast<unsigned char>(format), 0, n, division_hi, division_lo});
  for (const Bytes& t : tracks) {
    const Bytes c = chunk("MTrk", t);
    file.insert(file.end(), c.begin(), c.end());
  }
  return file;
}

const Bytes kEnd = {0x00, 0xFF, 0x2F, 0x00};

Bytes with_end(Bytes events) {
  events.insert(events.end(), kEnd.begin(), kEnd.end());
  return events;
}

bool write(const fs::path& path, const Bytes& bytes) {
  return hmp::fuzz::write_seed_file(path.string(), bytes.data(), bytes.size());
}

bool hand_made(const fs::path& dir) {
  // Format 0, two channels, running status (also across a meta event), velocity-0 note-offs.
  const Bytes running = with_end({0x00, 0x90, 60,   100,  0x00, 64,  90,   0x00, 0x91, 48,   80,   0x60, 0x90, 60,
                                  0,    0x00, 0xFF, 0x01, 0x01, 'x', 0x00, 64,   0,    0x30, 0x81, 48,   0});
  // Format 1: conductor track with tempo and time signature changes, a named track with a program.
  const Bytes conductor = with_end({0x00, 0xFF, 0x51, 0x03, 0x07, 0xA1, 0x20, 0x00, 0xFF, 0x58, 0x04, 3,
                                    2,    24,   8,    0x83, 0x00, 0xFF, 0x51, 0x03, 0x03, 0xD0, 0x90});
  const Bytes named = with_end(
      {0x00, 0xFF, 0x03, 0x04, 'L', 'e', 'a', 'd', 0x00, 0xC0, 40, 0x00, 0x90, 72, 64, 0x83, 0x60, 0x80, 72, 0});
  // Sysex (F0 and an F7 continuation) between notes; a drum note on channel 10.
  const Bytes sysex =
      with_end({0x00, 0xF0, 0x03, 0x7E, 0x7F, 0xF7, 0x00, 0x99, 36, 100, 0x10, 0xF7, 0x01, 0xF7, 0x10, 0x89, 36, 0});
  bool ok = true;
  ok = write(dir / "tiny-format0-running.mid", smf(0, 0x00, 0x60, {running})) && ok;
  ok = write(dir / "tiny-format1-tempo.mid", smf(1, 0x01, 0x80, {conductor, named})) && ok;
  ok = write(dir / "tiny-format2-patterns.mid", smf(2, 0x00, 0x60, {named, running})) && ok;
  ok = write(dir / "tiny-smpte.mid", smf(1, 0xE7, 0x28, {sysex})) && ok;  // −25 fps, 40 ticks per frame

  // RIFF RMID wrapper around a format 0 file.
  const Bytes inner = smf(0, 0x00, 0x60, {running});
  Bytes rmid = {'R', 'M', 'I', 'D'};
  const Bytes data = chunk("data", inner);
  rmid.insert(rmid.end(), data.begin(), data.end());
  Bytes riff = {'R', 'I', 'F', 'F'};
  const auto n = static_cast<unsigned>(rmid.size());
  for (int shift = 0; shift < 32; shift += 8) riff.push_back(static_cast<unsigned char>(n >> shift));
  riff.insert(riff.end(), rmid.begin(), rmid.end());
  ok = write(dir / "tiny-rmid.rmi", riff) && ok;

  // MThd of length 8 (2 extra bytes to honour) and an unknown chunk before the track.
  Bytes long_header = chunk("MThd", {0, 1, 0, 1, 0, 0x60, 0xAB, 0xCD});
  const Bytes unknown = chunk("XFIH", {1, 2, 3});
  const Bytes track = chunk("MTrk", sysex);
  for (const Bytes* b : {&unknown, &track}) long_header.insert(long_header.end(), b->begin(), b->end());
  ok = write(dir / "tiny-long-header.mid", long_header) && ok;
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir_text = hmp::fuzz::seed_dir(argc, argv);
  if (dir_text.empty()) return 2;
  const fs::path dir = dir_text;
  bool ok = hand_made(dir);
  const fs::path corpus = fs::path(HMP_TEST_DATA_DIR) / "midi";
  std::error_code ec;
  if (fs::is_directory(corpus, ec)) {
    for (const auto& e : fs::recursive_directory_iterator(corpus)) {
      if (!e.is_regular_file() || e.path().extension() != ".mid") continue;
      // Flatten the relative path into one name: the corpus has the same file names in several folders.
      std::string name = fs::relative(e.path(), corpus).generic_string();
      for (char& c : name) c = c == '/' ? '_' : c;
      fs::copy_file(e.path(), dir / name, fs::copy_options::overwrite_existing, ec);
      if (ec) {
        std::fprintf(stderr, "midi_seeds: cannot copy %s: %s\n", e.path().c_str(), ec.message().c_str());
        ok = false;
      }
    }
  } else {
    std::fprintf(stderr, "midi_seeds: %s not found; only the hand-made seeds are written\n", corpus.c_str());
  }
  return ok ? 0 : 1;
}
