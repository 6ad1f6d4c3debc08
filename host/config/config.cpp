#include "host/config/config.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <cmath>
#include <set>

#include "host/common/error.hpp"
#include "host/common/input_file.hpp"
#include "host/common/number_text.hpp"
#include "host/common/printable.hpp"
#include "shared/protocol/protocol.hpp"

namespace hmp::config {

namespace {

class Reader {
 public:
  explicit Reader(const std::string& path) : path_(printable(path)) {}

  [[noreturn]] void fail(const std::string& what) const { throw BadInput(path_ + ": " + what); }

  // Every key of `table` must be one of `known` (`where` is the dotted prefix for messages).
  void only(const toml::table& table, const std::string& where, const std::set<std::string>& known) const {
    for (const auto& [key, node] : table) {
      (void)node;
      const std::string k(key.str());
      if (!known.count(k)) fail("unknown key '" + (where.empty() ? k : where + "." + k) + "'");
    }
  }

  double number(const toml::node& n, const std::string& where) const {
    if (auto v = n.value<double>(); v && std::isfinite(*v)) return *v;
    // An integer beyond 2^53 is a number all the same (toml++ will not round it to a double): its range
    // is checked where it is used.
    if (const toml::value<std::int64_t>* i = n.as_integer()) return static_cast<double>(i->get());
    fail("'" + where + "' must be a finite number");
  }

  std::string text(const toml::node& n, const std::string& where) const {
    if (auto v = n.value<std::string>()) return *v;
    fail("'" + where + "' must be a string");
  }

  template <std::size_t N>
  std::array<double, N> numbers(const toml::node& n, const std::string& where) const {
    const toml::array* arr = n.as_array();
    if (!arr || arr->size() != N) fail("'" + where + "' must be an array of " + std::to_string(N) + " numbers");
    std::array<double, N> out{};
    for (std::size_t i = 0; i < N; ++i) out[i] = number(*arr->get(i), where + "[" + std::to_string(i) + "]");
    return out;
  }

  const toml::table& table(const toml::node& n, const std::string& where) const {
    if (const toml::table* t = n.as_table()) return *t;
    fail("'" + where + "' must be a table");
  }

 private:
  std::string path_;
};

envelope::Adsr read_preset(const Reader& r, const toml::table& t, const std::string& where) {
  r.only(t, where, {"attack_ms", "decay_ms", "release_ms", "sustain_pct", "final_pct"});
  envelope::Adsr a;
  auto get = [&](const char* key, double fallback) {
    const toml::node* n = t.get(key);
    return n ? r.number(*n, where + "." + key) : fallback;
  };
  const double attack = get("attack_ms", 0), decay = get("decay_ms", 0), release = get("release_ms", 0);
  const double sustain = get("sustain_pct", 100), final_pct = get("final_pct", 100);
  for (double ms : {attack, decay, release}) {
    if (ms < 0 || ms > 1e7) r.fail("'" + where + "': durations must be in [0, 1e7] ms");
  }
  if (sustain < 0 || sustain > 100 || final_pct < 0 || final_pct > 100) {
    r.fail("'" + where + "': sustain_pct and final_pct must be in [0, 100]");
  }
  a.attack_ms = static_cast<float>(attack);
  a.decay_ms = static_cast<float>(decay);
  a.release_ms = static_cast<float>(release);
  a.sustain = static_cast<float>(sustain / 100);
  a.final_ratio = static_cast<float>(final_pct / 100);
  return a;
}

}  // namespace

Config load(const std::string& path) {
  // Read here rather than by toml::parse_file: a directory or a missing file gets the message every file
  // the user names gets (host/common/input_file.hpp).
  const std::string text = read_input_file(path, std::uint64_t{16} << 20);
  toml::table root;
  try {
    root = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    throw BadInput(printable(path) + ":" + std::to_string(where.line) + ":" + std::to_string(where.column) + ": " +
                   std::string(e.description()));
  }
  const Reader r(path);
  r.only(root, "", {"mapping", "envelope", "presets", "gm", "measured", "device", "plant"});
  Config c;
  if (const toml::node* n = root.get("mapping")) {
    const auto& t = r.table(*n, "mapping");
    r.only(t, "mapping", {"mode", "key_scope", "freq_range", "amp_range_db"});
    if (auto* v = t.get("mode")) c.mapping_mode = r.text(*v, "mapping.mode");
    if (auto* v = t.get("key_scope")) c.key_scope = r.text(*v, "mapping.key_scope");
    if (auto* v = t.get("freq_range")) c.freq_range = r.numbers<2>(*v, "mapping.freq_range");
    if (auto* v = t.get("amp_range_db")) c.amp_range_db = r.numbers<2>(*v, "mapping.amp_range_db");
  }
  if (const toml::node* n = root.get("envelope")) {
    const auto& t = r.table(*n, "envelope");
    r.only(t, "envelope", {"default", "end_fade_ms", "polyphony"});
    if (auto* v = t.get("default")) c.envelope = r.text(*v, "envelope.default");
    if (auto* v = t.get("end_fade_ms")) c.end_fade_ms = r.number(*v, "envelope.end_fade_ms");
    if (auto* v = t.get("polyphony")) c.polyphony = r.text(*v, "envelope.polyphony");
  }
  if (const toml::node* n = root.get("presets")) {
    for (const auto& [key, node] : r.table(*n, "presets")) {
      std::string name(key.str());
      for (char& ch : name) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
      // A built-in's name is allowed (the user's measurement replaces Table 1's); names are not case-sensitive,
      // so two that differ only in case would be one preset, the last silently.
      if (c.presets.count(name) != 0)
        r.fail("presets." + printable(std::string(key.str())) + ": another preset has this name (case does not count)");
      c.presets[name] = read_preset(r, r.table(node, "presets." + name), "presets." + name);
    }
  }
  // program number → preset name: [gm] overrides `auto`; [measured] is what `hmp envelope measure` wrote.
  const auto program_table = [&](const char* table, std::map<std::uint8_t, std::string>& out) {
    const toml::node* n = root.get(table);
    if (n == nullptr) return;
    for (const auto& [key, node] : r.table(*n, table)) {
      const std::string k(key.str());
      const std::optional<long> program = whole_number(k, 0, 127);
      if (!program) r.fail(std::string(table) + ": key '" + printable(k) + "' must be a GM program number 0–127");
      const auto p = static_cast<std::uint8_t>(*program);
      if (out.count(p) != 0) r.fail(fmt::format("{}: program {} is given twice (key '{}')", table, p, printable(k)));
      out[p] = r.text(node, std::string(table) + "." + k);
    }
  };
  program_table("gm", c.gm);
  program_table("measured", c.measured);
  if (const toml::node* n = root.get("device")) {
    const auto& t = r.table(*n, "device");
    r.only(t, "device", {"tick_hz", "peak_force_n", "direction"});
    if (auto* v = t.get("tick_hz")) {
      const double hz = r.number(*v, "device.tick_hz");
      if (hz < 100 || hz > 100000 || hz != std::floor(hz))
        r.fail("'device.tick_hz' must be an integer in [100, 100000]");
      c.tick_hz = static_cast<std::uint32_t>(hz);
    }
    if (auto* v = t.get("peak_force_n")) {
      c.peak_force_n = r.number(*v, "device.peak_force_n");
      const auto most = static_cast<double>(protocol::kMaxPeakForceN);
      if (!(*c.peak_force_n > 0 && *c.peak_force_n <= most))
        r.fail(fmt::format("'device.peak_force_n' must be in (0, {:g}] N", most));
    }
    if (auto* v = t.get("direction")) {
      // Any direction, as a unit vector (the device takes nothing else).
      std::array<double, 3> d = r.numbers<3>(*v, "device.direction");
      const double length = std::hypot(d[0], d[1], d[2]);
      if (!(length > 1e-9 && std::isfinite(length))) r.fail("'device.direction' must be a finite, non-zero vector");
      for (double& x : d) x /= length;
      c.direction = d;
    }
  }
  if (const toml::node* n = root.get("plant")) {
    const auto& t = r.table(*n, "plant");
    PlantConfig& p = c.plant;
    const std::pair<const char*, std::optional<double>*> values[] = {{"string_stiffness", &p.string_stiffness},
                                                                     {"string_damping", &p.string_damping},
                                                                     {"grip_mass", &p.grip_mass},
                                                                     {"motor_inertia", &p.motor_inertia},
                                                                     {"motor_inductance", &p.motor_inductance},
                                                                     {"finger_stiffness", &p.finger_stiffness},
                                                                     {"finger_damping", &p.finger_damping},
                                                                     {"max_step", &p.max_step}};
    std::set<std::string> keys{"integrator"};
    for (const auto& [key, out] : values) keys.emplace(key);
    r.only(t, "plant", keys);
    for (const auto& [key, out] : values) {
      const toml::node* v = t.get(key);
      if (v == nullptr) continue;
      const double x = r.number(*v, std::string("plant.") + key);
      if (!(x > 0 && x <= kMaxPlantValue))
        r.fail(fmt::format("'plant.{}' must be positive and at most {}", key, short_number(kMaxPlantValue)));
      if (out == &p.max_step && x < kMinMaxStep)
        r.fail(fmt::format("'plant.max_step' must be at least {} s", short_number(kMinMaxStep)));
      *out = x;
    }
    if (auto* v = t.get("integrator")) p.integrator = r.text(*v, "plant.integrator");
  }
  return c;
}

}  // namespace hmp::config
