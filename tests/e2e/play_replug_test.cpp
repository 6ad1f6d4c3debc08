// A device that comes back (docs/player.md, "A device that is lost"): the link is cut mid-song; the player
// pauses, says so and waits; when the device returns it is greeted again and the song plays on from where
// it stopped, every note after the resume on its tick. Two returns: the cable put back on a device that
// ran on (the same simulated device), and a device that lost power (a fresh one). A key pressed while
// waiting acts when the device is back; quitting while waiting ends the run at once.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

#include "play_harness.hpp"
#include "host/transport/sim_transport.hpp"

namespace {

using namespace std::chrono_literals;
using hmp::transport::Received;
using hmp::transport::Report;
using hmp::transport::Timeout;
using Clock = std::chrono::steady_clock;
namespace test = hmp::test;

constexpr std::uint32_t kFlute = 1;
constexpr double kFrom = 130, kTo = 136;

// A cable between the host and a simulated device: cut() pulls it (the host sees the link close); the
// device behind it is untouched.
class Cable : public hmp::transport::Transport {
 public:
  explicit Cable(hmp::transport::SimTransport& device) : device_(device) {}
  bool send(const Report& r) override { return !cut_ && device_.send(r); }
  Received receive(Report& out, Timeout t) override {
    if (cut_) return Received::closed;
    const Received got = device_.receive(out, t);
    return cut_ ? Received::closed : got;
  }
  std::string name() const override { return "cable to sim"; }
  void close() override { cut_ = true; }
  bool is_open() const override { return !cut_; }
  std::string closed_reason() const override { return cut_ ? "cable pulled" : ""; }
  hmp::transport::LinkCounters counters() const override { return device_.counters(); }
  void cut() { cut_ = true; }

 private:
  hmp::transport::SimTransport& device_;
  std::atomic<bool> cut_{false};
};

// The device the player finds again: nothing until back() is called, then a new cable to `device`.
struct Replug {
  std::atomic<hmp::transport::SimTransport*> device{nullptr};
  std::unique_ptr<Cable> cable;  // touched on the player's thread only
  std::atomic<int> tries{0};
  hmp::transport::Transport* find() {
    ++tries;
    hmp::transport::SimTransport* d = device.load();
    if (d == nullptr) return nullptr;
    cable = std::make_unique<Cable>(*d);
    return cable.get();
  }
};

struct Messages {
  std::mutex mutex;
  std::vector<std::string> lines;
  bool said(const std::string& part) {
    std::lock_guard lock(mutex);
    for (const std::string& l : lines) {
      if (l.find(part) != std::string::npos) return true;
    }
    return false;
  }
};

bool wait_until(const std::function<bool()>& done, std::chrono::milliseconds limit) {
  const auto deadline = Clock::now() + limit;
  while (!done()) {
    if (Clock::now() > deadline) return false;
    std::this_thread::sleep_for(5ms);
  }
  return true;
}

struct Replugged {
  hmp::transport::SimTransport first;
  Cable cable{first};
  Replug replug;
  Messages messages;
  std::unique_ptr<test::Session> session;
  std::int64_t lost_at_us = 0;  // the song time the player stopped at

  Replugged() {
    hmp::player::PlayerOptions o = test::passage(kFlute, kFrom, kTo);
    o.find_device = [this] { return replug.find(); };
    o.find_period = 50ms;
    o.on_message = [this](const std::string& line) {
      std::lock_guard lock(messages.mutex);
      messages.lines.push_back(line);
    };
    session = std::make_unique<test::Session>(cable, std::move(o));
  }

  // Plays 1.5 s, pulls the cable, checks the player waits paused, and leaves it waiting 1 s.
  void play_then_pull() {
    session->start();
    std::this_thread::sleep_for(1500ms);
    cable.cut();
    ASSERT_TRUE(wait_until([&] { return session->player().snapshot().device_lost; }, 1000ms))
        << "the loss was not noticed within 1 s";
    const hmp::player::Snapshot lost = session->player().snapshot();
    EXPECT_TRUE(lost.paused);
    lost_at_us = lost.song_us;
    EXPECT_GT(lost_at_us, static_cast<std::int64_t>(kFrom * 1e6));
    EXPECT_TRUE(messages.said("device lost — plug it back in, or q to quit"));
    std::this_thread::sleep_for(1000ms);
    // Nothing moved while it was gone: the song waits, and the player kept looking for the device.
    EXPECT_EQ(session->player().snapshot().song_us, lost_at_us);
    EXPECT_GE(replug.tries.load(), 10);
  }

  // After the return: the passage ends normally; every note after the resume once and on its tick; every
  // note before the cable was pulled, except the few in flight, once as well.
  void expect_played_on() {
    session->join();
    ASSERT_TRUE(session->outcome().has_value()) << session->error();
    EXPECT_EQ(*session->outcome(), hmp::player::Outcome::finished);
    const hmp::player::Counters c = session->player().counters();
    EXPECT_EQ(c.recoveries, 1u);
    EXPECT_EQ(c.rejected, 0u);
    EXPECT_TRUE(messages.said("is back: playing on at"));
    std::map<std::pair<int, double>, int> times_started;
    for (const hmp::player::StartedNote& n : session->started()) {
      ++times_started[{n.origin.key, n.origin.start_s}];
      if (n.origin.start_s * 1e6 >= static_cast<double>(lost_at_us)) {
        EXPECT_EQ(n.actual_tick, n.scheduled_tick)
            << "after the resume: key " << int(n.origin.key) << " at " << n.origin.start_s;
      }
    }
    const double lost_s = static_cast<double>(lost_at_us) / 1e6;
    int after = 0;
    for (const auto& note : test::passage_notes(kFlute, kFrom, kTo)) {
      const int n = times_started[note];
      if (note.second >= lost_s) {
        ++after;
        EXPECT_EQ(n, 1) << "key " << note.first << " at " << note.second << " (resumed at " << lost_s << ")";
      } else if (note.second < lost_s - 0.3) {
        EXPECT_EQ(n, 1) << "key " << note.first << " at " << note.second << " (before the cut)";
      } else {
        EXPECT_LE(n, 1);  // in flight when the cable went: its Started report may be lost with it
      }
    }
    EXPECT_GT(after, 5) << "too few notes after the resume to tell";
  }
};

TEST(PlayReplug, CablePutBackOnADeviceThatRanOn) {
  Replugged run;
  run.play_then_pull();
  run.replug.device = &run.first;
  run.expect_played_on();
}

TEST(PlayReplug, DeviceThatLostPowerIsGreetedFreshAndPlaysOn) {
  Replugged run;
  run.play_then_pull();
  hmp::transport::SimTransport fresh;
  run.replug.device = &fresh;
  run.expect_played_on();
  const std::uint32_t on_fresh = fresh.with_device([](hmp::sim::SimDevice& d) { return d.core().stats().started; });
  EXPECT_GT(on_fresh, 5u);
}

// A key pressed while the device is away (here t, the next track) waits for it, as docs/player.md says and
// as the window's seeks do: it acts once the device is back.
TEST(PlayReplug, AKeyPressedWhileWaitingActsWhenTheDeviceIsBack) {
  Replugged run;
  run.play_then_pull();
  EXPECT_EQ(run.session->player().snapshot().track, kFlute);
  run.session->player().post(hmp::player::Command::next_track);
  std::this_thread::sleep_for(200ms);
  EXPECT_EQ(run.session->player().snapshot().track, kFlute) << "switched without a device";
  run.replug.device = &run.first;
  EXPECT_TRUE(wait_until([&] { return run.session->player().snapshot().track == kFlute + 1; }, 3000ms))
      << "the key pressed while waiting was lost";
  // The snapshot carries the player's last message, which the window shows on its top line a while.
  EXPECT_TRUE(wait_until([&] { return run.session->player().snapshot().message.find("haptic track 2") == 0; }, 1000ms))
      << run.session->player().snapshot().message;
  run.session->player().post(hmp::player::Command::quit);
  run.session->join();
}

TEST(PlayReplug, QuitWhileWaitingEndsAtOnce) {
  Replugged run;
  run.play_then_pull();
  const auto asked = Clock::now();
  run.session->player().post(hmp::player::Command::quit);
  run.session->join();
  EXPECT_LT(Clock::now() - asked, 500ms);
  ASSERT_TRUE(run.session->outcome().has_value()) << run.session->error();
  EXPECT_EQ(*run.session->outcome(), hmp::player::Outcome::quit);
  EXPECT_FALSE(run.session->player().snapshot().device_lost);
}

}  // namespace
