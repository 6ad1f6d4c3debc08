#pragma once
// The simulated board (design §13 `sim`): the firmware core built natively on a deterministic virtual
// clock. Nothing runs by itself: advance(n) runs the tick interrupt n times, each followed by the core's
// background work (Core::poll: sending the tick's reports, preparing the voices of the next notes), as a
// main loop that always keeps up would; reports go in and come out through the same 64-byte interface as
// over USB HID. Used by the firmware tests and as the default
// device of `hmp play`.
//
// With a plant (SimOptions::plant, design §12) the board has motors: the core's SPIDAR drive runs, each
// tick's eight duties go into plant.step(duties, 1/tick_hz), and the plant's encoder counts (quantised
// like the real ones) are what the drive reads on the next tick. Without one (the default) the board has
// no motors and the core only computes the vibration value, as on the QEMU board.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "boards/sim/plant/plant.hpp"
#include "firmware/core.hpp"

namespace hmp::sim {

// The scene the drive renders into (design §16: only what it needs): a translation-only grip held by a
// finger (the force a user feels needs a hand holding the grip; without one a force-controlled grip
// falls under gravity), gravity on.
plant::PlantParams drive_scene();

struct PlantOptions {
  plant::PlantParams params = drive_scene();
  double bias_tension = 0.3;  // N in every string at reset (the firmware's default t_min)
  // The plant is stepped in this many equal parts per tick (duties held), and the observer sees each:
  // finer than the tick for measurements (the force between ticks), the same physics either way.
  int observe_substeps = 1;
};

struct SimOptions {
  std::uint32_t tick_hz = fw::kDefaultTickHz;
  std::uint64_t first_tick = 0;
  std::optional<PlantOptions> plant;  // none: a board without motors
  fw::DriveParams drive{};            // the firmware drive's configuration
};

class SimDevice {
 public:
  // Device reports held for the host before the board reports "no room" (counted by the core).
  static constexpr std::size_t kMaxPendingReports = 1u << 16;
  static constexpr std::size_t kMaxLogLines = 256;

  explicit SimDevice(std::uint32_t tick_hz = fw::kDefaultTickHz, std::uint64_t first_tick = 0);
  explicit SimDevice(const SimOptions& options);
  SimDevice(const SimDevice&) = delete;
  SimDevice& operator=(const SimDevice&) = delete;

  // ---- host → device ----
  // Hands the report to the core now (it is handled on the next tick). false: the core's inbox was
  // full and the report is lost, as over a UART with no flow control.
  bool send_to_device(const protocol::Report& report);
  // Like a USB transfer the device NAKs while busy: runs ticks until the inbox has room, then sends.
  // Returns the number of ticks it had to run.
  std::uint64_t deliver(const protocol::Report& report);

  // ---- device → host ----
  bool poll_report(protocol::Report& out);  // oldest first; false when none
  std::size_t pending_reports() const { return reports_.size(); }
  void clear_reports() { reports_.clear(); }

  // ---- virtual time ----
  // Runs the tick interrupt `ticks` times; if `record` is given it receives one output sample per tick.
  // Each tick first advances the tick counter: the samples are those of ticks tick()+1 … tick()+ticks
  // (tick() read before the call). A report sent while tick() == k arrived during tick k (a SyncReply
  // says k) and is handled at the start of tick k+1, so a note scheduled for k+1 still starts on time.
  void advance(std::uint64_t ticks, float* record = nullptr);
  std::vector<float> record(std::size_t ticks);
  // What the board's timer reports as the fraction of the present tick elapsed (2^32 = one tick) for
  // the next packets; the virtual clock itself only moves in whole ticks.
  void set_subtick(std::uint32_t fraction) { subtick_ = fraction; }
  // Whether the background prepares voices after each tick (default on). Off: the tick sets up every
  // note itself, as with a main loop that never gets to it (reports are sent either way).
  void set_prepare_voices(bool on) { prepare_voices_ = on; }

  // ---- inspection ----
  const fw::Core& core() const { return core_; }
  std::uint64_t tick() const { return core_.tick(); }
  float last_output() const { return last_output_; }
  const std::deque<std::string>& log() const { return log_; }  // the last kMaxLogLines lines
  void set_log_echo(bool on) { echo_log_ = on; }               // also print log lines on stderr

  // ---- the plant (null / no-ops without one) ----
  const plant::Plant* plant() const { return plant_.get(); }
  // The hand on the grip moves: the finger's anchor goes to `anchor` (m, device frame).
  void move_hand(const plant::Vec3d& anchor) {
    if (plant_) plant_->set_finger_anchor(anchor);
  }
  bool plant_unstable() const { return plant_ != nullptr && plant_->unstable(); }  // also logged once
  const float (&duties() const)[fw::kMotorCount] { return duty_; }                 // the last ones the core sent
  // Called after every observed part of a tick (see PlantOptions::observe_substeps): plant time (s), output.
  using PlantObserver = std::function<void(double, const plant::PlantOutput&)>;
  void set_plant_observer(PlantObserver observer) { observer_ = std::move(observer); }
  // Fault injection: edit the counts the core reads, or the duties that reach the motors.
  using EncoderHook = std::function<void(std::int32_t (&)[fw::kMotorCount])>;
  using DutyHook = std::function<void(float (&)[fw::kMotorCount])>;
  void set_encoder_hook(EncoderHook hook) { encoder_hook_ = std::move(hook); }
  void set_duty_hook(DutyHook hook) { duty_hook_ = std::move(hook); }

 private:
  static fw::BoardSeam make_seam(SimDevice* self, bool motors);
  static void on_read_encoders(void* ctx, std::int32_t (&counts)[fw::kMotorCount]);
  static void on_motor_output(void* ctx, const float (&duty)[fw::kMotorCount]);
  void step_plant();
  static void on_output(void* ctx, float value);
  static bool on_send(void* ctx, const protocol::Report& report);
  static void on_log(void* ctx, const char* line);
  static std::uint32_t on_subtick(void* ctx);

  struct Report {
    std::uint8_t bytes[protocol::kReportSize];
  };

  std::deque<Report> reports_;
  std::deque<std::string> log_;
  float* record_ = nullptr;  // during advance(): where the next sample goes
  float last_output_ = 0.0f;
  std::uint32_t subtick_ = 0;
  bool echo_log_ = false;
  bool prepare_voices_ = true;
  std::unique_ptr<plant::Plant> plant_;
  int observe_substeps_ = 1;
  bool unstable_logged_ = false;
  float duty_[fw::kMotorCount]{};
  PlantObserver observer_;
  EncoderHook encoder_hook_;
  DutyHook duty_hook_;
  fw::Core core_;  // last: its seam points at the members above
};

}  // namespace hmp::sim
