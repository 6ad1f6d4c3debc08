#pragma once
// Two connected in-memory ends (tests, and any in-process peer that wants a Transport): what one end
// sends, the other receives, in order. Closing either end closes the link for both; each end still
// receives what was queued for it before the close.
#include <memory>
#include <string>
#include <utility>

#include "host/transport/transport.hpp"

namespace hmp::transport {

class LoopbackTransport final : public Transport {
 public:
  using Pair = std::pair<std::unique_ptr<LoopbackTransport>, std::unique_ptr<LoopbackTransport>>;
  // first: the host end, second: the device end (the names say which).
  static Pair make_pair(const std::string& name = "loopback");
  ~LoopbackTransport() override;

  bool send(const Report& report) override;
  Received receive(Report& out, Timeout timeout) override;
  std::string name() const override { return name_; }
  void close() override;
  bool is_open() const override;
  std::string closed_reason() const override;
  LinkCounters counters() const override;

 private:
  struct Shared;
  LoopbackTransport(std::shared_ptr<Shared> shared, int side, std::string name);

  std::shared_ptr<Shared> shared_;
  int side_;  // 0 or 1: this end receives from queue[side_] and sends into queue[1 - side_]
  std::string name_;
};

}  // namespace hmp::transport
