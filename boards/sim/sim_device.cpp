#include "boards/sim/sim_device.hpp"

#include <cstdio>

namespace hmp::sim {

plant::PlantParams drive_scene() {
  plant::PlantParams p;
  p.scene.translation_only = true;
  p.scene.finger = true;
  return p;
}

namespace {
std::unique_ptr<plant::Plant> make_plant(const std::optional<PlantOptions>& o) {
  if (!o) return nullptr;
  auto p = std::make_unique<plant::Plant>(o->params);
  p->reset(o->bias_tension);
  return p;
}
}  // namespace

SimDevice::SimDevice(std::uint32_t tick_hz, std::uint64_t first_tick)
    : core_(make_seam(this, false), tick_hz, first_tick) {}

SimDevice::SimDevice(const SimOptions& options)
    : plant_(make_plant(options.plant)),
      observe_substeps_(options.plant && options.plant->observe_substeps > 1 ? options.plant->observe_substeps : 1),
      core_(make_seam(this, options.plant.has_value()), options.tick_hz, options.first_tick, options.drive) {}

fw::BoardSeam SimDevice::make_seam(SimDevice* self, bool motors) {
  fw::BoardSeam seam;
  seam.ctx = self;
  seam.output = &SimDevice::on_output;
  seam.send = &SimDevice::on_send;
  seam.log = &SimDevice::on_log;
  seam.subtick = &SimDevice::on_subtick;
  if (motors) {
    seam.read_encoders = &SimDevice::on_read_encoders;
    seam.motor_output = &SimDevice::on_motor_output;
  }
  seam.id = protocol::Board::sim;
  return seam;
}

void SimDevice::on_read_encoders(void* ctx, std::int32_t (&counts)[fw::kMotorCount]) {
  auto* self = static_cast<SimDevice*>(ctx);
  const plant::PlantOutput& out = self->plant_->output();
  for (int i = 0; i < fw::kMotorCount; ++i) counts[i] = out.counts[i];
  if (self->encoder_hook_) self->encoder_hook_(counts);
}

void SimDevice::on_motor_output(void* ctx, const float (&duty)[fw::kMotorCount]) {
  auto* self = static_cast<SimDevice*>(ctx);
  for (int i = 0; i < fw::kMotorCount; ++i) self->duty_[i] = duty[i];
}

// The tick's duties act until the next tick; the counts at the end are what the drive reads next.
void SimDevice::step_plant() {
  float duty[fw::kMotorCount];
  for (int i = 0; i < fw::kMotorCount; ++i) duty[i] = duty_[i];
  if (duty_hook_) duty_hook_(duty);
  const double dt = 1.0 / static_cast<double>(core_.tick_hz()) / observe_substeps_;
  for (int k = 0; k < observe_substeps_; ++k) {
    const plant::PlantOutput& out = plant_->step(duty, dt);
    if (observer_) observer_(plant_->time(), out);
  }
  if (plant_->unstable() && !unstable_logged_) {
    unstable_logged_ = true;
    on_log(this, "plant unstable: the integrator's step is past its stable limit (results invalid)");
  }
}

void SimDevice::on_output(void* ctx, float value) {
  auto* self = static_cast<SimDevice*>(ctx);
  self->last_output_ = value;
  if (self->record_ != nullptr) *self->record_++ = value;
}

bool SimDevice::on_send(void* ctx, const protocol::Report& report) {
  auto* self = static_cast<SimDevice*>(ctx);
  if (self->reports_.size() >= kMaxPendingReports) return false;
  Report r;
  for (std::size_t i = 0; i < protocol::kReportSize; ++i) r.bytes[i] = report[i];
  self->reports_.push_back(r);
  return true;
}

void SimDevice::on_log(void* ctx, const char* line) {
  auto* self = static_cast<SimDevice*>(ctx);
  if (self->echo_log_) {
    std::fprintf(stderr, "[sim %llu] %s\n", static_cast<unsigned long long>(self->tick()), line);
  }
  if (self->log_.size() >= kMaxLogLines) self->log_.pop_front();
  self->log_.emplace_back(line);
}

std::uint32_t SimDevice::on_subtick(void* ctx) { return static_cast<SimDevice*>(ctx)->subtick_; }

bool SimDevice::send_to_device(const protocol::Report& report) { return core_.on_packet(report); }

std::uint64_t SimDevice::deliver(const protocol::Report& report) {
  std::uint64_t waited = 0;
  while (!core_.inbox_has_room()) {
    advance(1);
    ++waited;
  }
  core_.on_packet(report);
  return waited;
}

bool SimDevice::poll_report(protocol::Report& out) {
  if (reports_.empty()) return false;
  for (std::size_t i = 0; i < protocol::kReportSize; ++i) out[i] = reports_.front().bytes[i];
  reports_.pop_front();
  return true;
}

void SimDevice::advance(std::uint64_t ticks, float* record) {
  record_ = record;
  for (std::uint64_t i = 0; i < ticks; ++i) {
    core_.on_tick();
    if (plant_) step_plant();
    // The background's parts, as the board's main loop runs them between ticks (Core::poll).
    core_.plan_drive();
    core_.send_reports();
    if (prepare_voices_) core_.prepare_voices();
  }
  record_ = nullptr;
}

std::vector<float> SimDevice::record(std::size_t ticks) {
  std::vector<float> out(ticks);
  advance(ticks, out.data());
  return out;
}

}  // namespace hmp::sim
