#include "host/transport/host_session.hpp"

#include <stdexcept>
#include <string>

namespace hmp::transport {

std::uint16_t HostSession::number(protocol::Message& m, protocol::Report& out) {
  m.seq = next_seq();
  if (!protocol::encode(m, out)) {
    throw std::logic_error(std::string("host built an invalid ") + protocol::name(m.type) + " report");
  }
  last_sent_ = m.seq;
  if (is_note_report(m.type)) in_flight_.push_back(m.seq);
  return m.seq;
}

void HostSession::on_status(const protocol::Status& s) {
  status_ = s;
  if (s.last_seq == 0) return;  // nothing processed yet
  while (!in_flight_.empty() && seq_not_after(in_flight_.front(), s.last_seq)) in_flight_.pop_front();
}

void HostSession::restart(const std::optional<protocol::Status>& first_status) {
  in_flight_.clear();
  status_.reset();
  if (first_status) on_status(*first_status);
}

int HostSession::credit() const {
  if (!status_) return 0;
  return static_cast<int>(status_->queue_free) - static_cast<int>(in_flight_.size());
}

bool HostSession::processed(std::uint16_t seq) const {
  return status_ && status_->last_seq != 0 && seq_not_after(seq, status_->last_seq);
}

}  // namespace hmp::transport
