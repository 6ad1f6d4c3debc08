// transport::say_hello against a board that is still starting: whatever arrives before it listens is
// lost, so the Hello must go out again until it is answered. The board is the simulated device (the
// firmware core) behind a link that drops every report sent before a given moment.
#include <gtest/gtest.h>

#include <chrono>

#include "host/transport/handshake.hpp"
#include "host/transport/sim_transport.hpp"

namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
namespace t = hmp::transport;

// A link to the simulated device that is deaf until `listens_at`: reports sent before then vanish, as
// bytes do on a UART that is not enabled yet.
class StartingBoard final : public t::Transport {
 public:
  explicit StartingBoard(Clock::duration deaf_for) : listens_at_(Clock::now() + deaf_for) {}
  bool send(const t::Report& r) override {
    ++sent_;
    if (Clock::now() < listens_at_) {
      ++lost_;
      return true;
    }
    return sim_.send(r);
  }
  t::Received receive(t::Report& out, t::Timeout timeout) override { return sim_.receive(out, timeout); }
  std::string name() const override { return "starting-board"; }
  void close() override { sim_.close(); }
  bool is_open() const override { return sim_.is_open(); }
  std::string closed_reason() const override { return sim_.closed_reason(); }
  t::LinkCounters counters() const override { return sim_.counters(); }

  int sent() const { return sent_; }
  int lost() const { return lost_; }

 private:
  t::SimTransport sim_;
  Clock::time_point listens_at_;
  int sent_ = 0, lost_ = 0;
};

TEST(Handshake, HelloIsResentUntilABoardThatStartsLateAnswers) {
  StartingBoard board(350ms);
  const auto t0 = Clock::now();
  const auto id = t::say_hello(board, 7, 2000ms);
  const auto took = Clock::now() - t0;
  ASSERT_TRUE(id.has_value()) << "sent " << board.sent() << " Hellos, " << board.lost() << " lost";
  EXPECT_GE(board.lost(), 1) << "the board must have missed the first Hello, or the test proves nothing";
  EXPECT_EQ(id->hellos_sent, board.sent());
  // Once the board listens it answers within a tick; one more copy may cross the answer on a busy machine.
  EXPECT_LE(id->hellos_sent, board.lost() + 2) << "Hellos go on after the board has answered";
  EXPECT_TRUE(id->compatible());
  ASSERT_TRUE(id->status.has_value());
  EXPECT_EQ(id->status->last_seq, 7u) << "every copy carries the same number";
  EXPECT_GE(took, 350ms);
}

TEST(Handshake, AnAnsweringBoardGetsOneHello) {
  StartingBoard board(0ms);
  const auto id = t::say_hello(board, 1, 2000ms);
  ASSERT_TRUE(id.has_value());
  EXPECT_EQ(id->hellos_sent, 1);
  EXPECT_EQ(board.sent(), 1);
}

TEST(Handshake, ABoardThatNeverListensGetsAHelloEveryResendPeriodUntilTheDeadline) {
  StartingBoard board(1h);
  const auto t0 = Clock::now();
  const auto id = t::say_hello(board, 1, 500ms, 100ms);
  const auto took = Clock::now() - t0;
  EXPECT_FALSE(id.has_value());
  EXPECT_GE(took, 500ms);
  // One at once, then one each 100 ms: 5 by 400 ms (a busy machine may wake late and send fewer, never more).
  EXPECT_LE(board.sent(), 6);
  EXPECT_GE(board.sent(), 2);
}

}  // namespace
