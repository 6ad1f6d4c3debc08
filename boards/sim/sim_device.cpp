#include "boards/sim/sim_device.hpp"

#include <cstdio>

namespace hmp::sim {

SimDevice::SimDevice(std::uint32_t tick_hz, std::uint64_t first_tick)
    : core_(make_seam(this), tick_hz, first_tick) {}

fw::BoardSeam SimDevice::make_seam(SimDevice* self) {
  fw::BoardSeam seam;
  seam.ctx = self;
  seam.output = &SimDevice::on_output;
  seam.send = &SimDevice::on_send;
  seam.log = &SimDevice::on_log;
  seam.subtick = &SimDevice::on_subtick;
  seam.id = protocol::Board::sim;
  return seam;
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
  for (std::uint64_t i = 0; i < ticks; ++i) core_.on_tick();
  record_ = nullptr;
}

std::vector<float> SimDevice::record(std::size_t ticks) {
  std::vector<float> out(ticks);
  advance(ticks, out.data());
  return out;
}

}  // namespace hmp::sim
