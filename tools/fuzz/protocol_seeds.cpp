// Writes the seed corpus of fuzz_protocol: one valid report per message type (notes and started at every
// count), so the fuzzer starts from inputs that get past the type and range checks.
#include <cstdio>
#include <string>

#include "seed_file.hpp"
#include "shared/protocol/protocol.hpp"

namespace protocol = hmp::protocol;
using protocol::Type;

namespace {

bool write_seed(const std::string& dir, const std::string& name, const protocol::Message& m) {
  protocol::Report r;
  if (!protocol::encode(m, r)) {
    std::fprintf(stderr, "protocol_seeds: %s does not encode\n", name.c_str());
    return false;
  }
  return hmp::fuzz::write_seed_file(dir + "/" + name + ".bin", r, sizeof r);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = hmp::fuzz::seed_dir(argc, argv);
  if (dir.empty()) return 2;
  bool ok = true;
  const Type types[] = {Type::hello,     Type::sync,  Type::long_note,   Type::preset,     Type::settings,
                        Type::transport, Type::estop, Type::hello_reply, Type::sync_reply, Type::status};
  for (Type t : types) ok = write_seed(dir, protocol::name(t), protocol::make(t, 1)) && ok;

  for (std::uint8_t count = 1; count <= protocol::kNotesPerBatch; ++count) {
    protocol::Message notes = protocol::make(Type::notes, count);
    notes.notes.count = count;
    notes.notes.base_tick = 1000;
    for (std::uint8_t i = 0; i < count; ++i)
      notes.notes.notes[i] = {static_cast<std::uint8_t>(i * 10), i, 250, (100u + i) << 20, 40000};
    ok = write_seed(dir, "notes_" + std::to_string(count), notes) && ok;

    protocol::Message started = protocol::make(Type::started, count);
    started.started.count = count;
    for (std::uint8_t i = 0; i < count; ++i) started.started.entries[i] = {7, i, 1000u + i, 1000u + i};
    ok = write_seed(dir, "started_" + std::to_string(count), started) && ok;

    protocol::Message live = protocol::make(Type::live, count);
    live.live.count = count;
    for (std::uint8_t i = 0; i < count; ++i) {
      const auto op = static_cast<protocol::LiveOp>(1 + i % 3);
      live.live.events[i] = {op, static_cast<std::uint8_t>(60 + i), 0, 0, 0};
      if (op == protocol::LiveOp::on)
        live.live.events[i] = {op, static_cast<std::uint8_t>(60 + i), 2, 200u << 20, 40000};
      if (op == protocol::LiveOp::bend) live.live.events[i].freq_q20 = 210u << 20;
    }
    ok = write_seed(dir, "live_" + std::to_string(count), live) && ok;
  }
  protocol::Message error = protocol::make(Type::error, 1);
  error.error = {protocol::ErrorCode::queue_full, 9, static_cast<std::uint8_t>(Type::notes)};
  ok = write_seed(dir, "error", error) && ok;
  protocol::Message seek = protocol::make(Type::transport, 2);
  seek.transport = {protocol::TransportOp::seek, 123456};
  ok = write_seed(dir, "transport_seek", seek) && ok;
  return ok ? 0 : 1;
}
