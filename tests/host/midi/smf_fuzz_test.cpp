// 10,000 seeded mutations of the corpus files (byte changes, bit flips, truncation, insertions, huge length
// fields, spliced chunks): the reader returns a consistent song or throws BadInput, never anything else,
// and each read takes well under a second.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "host/common/error.hpp"
#include "host/midi/smf_reader.hpp"

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

namespace {

std::vector<Bytes> corpus() {
  std::vector<Bytes> files;
  for (const auto& e : fs::recursive_directory_iterator(fs::path(HMP_TEST_DATA_DIR) / "midi")) {
    if (!e.is_regular_file()) continue;
    const std::string ext = e.path().extension().string();
    if (ext != ".mid" && ext != ".syx") continue;
    std::ifstream in(e.path(), std::ios::binary);
    files.emplace_back((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }
  return files;
}

void mutate(Bytes& b, std::mt19937& rng) {
  auto pick = [&](std::size_t n) { return n == 0 ? std::size_t{0} : static_cast<std::size_t>(rng() % n); };
  const int edits = 1 + static_cast<int>(rng() % 8);
  for (int e = 0; e < edits; ++e) {
    switch (rng() % 7) {
      case 0:  // random byte
        if (!b.empty()) b[pick(b.size())] = static_cast<std::uint8_t>(rng());
        break;
      case 1:  // bit flip
        if (!b.empty()) b[pick(b.size())] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
        break;
      case 2:  // truncate
        b.resize(pick(b.size() + 1));
        break;
      case 3: {  // insert 1–16 random bytes
        const std::size_t at = pick(b.size() + 1);
        Bytes ins(1 + pick(16));
        for (auto& x : ins) x = static_cast<std::uint8_t>(rng());
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(at), ins.begin(), ins.end());
        break;
      }
      case 4:  // a huge 32-bit field (chunk lengths live in such fields)
        if (b.size() >= 4) {
          const std::size_t at = pick(b.size() - 3);
          const std::uint8_t v = (rng() % 2) ? 0xFF : 0x7F;
          b[at] = v, b[at + 1] = 0xFF, b[at + 2] = 0xFF, b[at + 3] = 0xFF;
        }
        break;
      case 5: {  // duplicate a span (repeats chunks and events)
        if (b.empty()) break;
        const std::size_t from = pick(b.size());
        const std::size_t len = std::min(b.size() - from, 1 + pick(64));
        const Bytes span(b.begin() + static_cast<std::ptrdiff_t>(from),
                         b.begin() + static_cast<std::ptrdiff_t>(from + len));
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(pick(b.size() + 1)), span.begin(), span.end());
        break;
      }
      default:  // a status byte or continuation byte where data was
        if (!b.empty()) b[pick(b.size())] = static_cast<std::uint8_t>(0x80 | rng());
        break;
    }
  }
}

void check_consistent(const hmp::midi::ReadResult& r) {
  const auto& s = r.song;
  std::uint64_t counted = 0;
  for (const auto& t : s.tracks) {
    counted += t.note_count;
    ASSERT_LE(t.end_tick, s.end_tick);
  }
  ASSERT_EQ(counted, s.notes.size());
  for (const auto& n : s.notes) {
    ASSERT_LT(n.track, s.tracks.size());
    ASSERT_LT(n.channel, 16);
    ASSERT_LT(n.key, 128);
    ASSERT_GE(n.velocity, 1);
    ASSERT_LT(n.velocity, 128);
    ASSERT_LE(n.start_tick, n.end_tick);
    ASSERT_LE(s.start_us(n), s.end_us(n));
    ASSERT_GE(s.start_us(n), 0);
    ASSERT_LE(n.end_tick, s.tracks[n.track].end_tick);
    ASSERT_LE(s.end_us(n), s.duration_us);
  }
  ASSERT_LE(r.warnings.size(), 201u);
}

}  // namespace

TEST(MidiFuzz, MutatedCorpusNeverCrashesOrHangs) {
  const std::vector<Bytes> files = corpus();
  ASSERT_GT(files.size(), 50u);
  std::mt19937 rng(20240613);
  int ok = 0, rejected = 0;
  double slowest_ms = 0;
  for (int i = 0; i < 10000; ++i) {
    Bytes b = files[rng() % files.size()];
    mutate(b, rng);
    const auto t0 = std::chrono::steady_clock::now();
    try {
      const hmp::midi::ReadResult r = hmp::midi::read_smf(b);
      check_consistent(r);
      if (testing::Test::HasFatalFailure()) {
        ADD_FAILURE() << "inconsistent song from mutation " << i;
        return;
      }
      ++ok;
    } catch (const hmp::BadInput& e) {
      ASSERT_NE(std::string(e.what()), "");
      ++rejected;
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    slowest_ms = std::max(slowest_ms, ms);
    ASSERT_LT(ms, 1000.0) << "mutation " << i;
  }
  // Both outcomes must occur, or the mutations are not exercising the reader.
  EXPECT_GT(ok, 1000);
  EXPECT_GT(rejected, 100);
  RecordProperty("slowest_ms", std::to_string(slowest_ms));
  std::printf("ok %d, rejected %d, slowest read %.3f ms\n", ok, rejected, slowest_ms);
}
