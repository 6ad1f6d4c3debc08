#include "host/modules/module_loader.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <climits>
#include <cstdlib>
#include <map>
#include <mutex>

namespace hmp::modules {
namespace {

struct Slot {
  void* backend = nullptr;
  std::string why;  // empty when loaded
};

std::mutex g_mutex;
std::map<std::string, Slot>& slots() {
  static std::map<std::string, Slot> s;
  return s;
}

// The running program's folder. /proc/self/exe names the real file even when hmp was started through a
// symbolic link (e.g. /usr/local/bin/hmp → /opt/hmp/bin/hmp), so an installed tree can be moved whole.
std::string program_dir() {
  char path[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", path, sizeof path - 1);
  if (n <= 0) return ".";
  const std::string exe(path, static_cast<std::size_t>(n));
  const std::size_t slash = exe.rfind('/');
  return slash == std::string::npos ? "." : exe.substr(0, slash);
}

Slot open_module(const std::string& name, int abi) {
  const std::string file = module_dir() + "/hmp-" + name + ".so";
  // RTLD_LOCAL: a module's libraries stay out of the symbol scope of everything loaded later (the GL
  // driver the view loads must not bind to FluidSynth's GLib, say). RTLD_NOW: a missing symbol is found
  // here, as one message, not as a crash in the middle of a song.
  void* handle = ::dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* error = ::dlerror();
    return {nullptr, error != nullptr ? error : file + ": cannot be loaded"};
  }
  using Entry = const void* (*)(int);
  auto entry = reinterpret_cast<Entry>(::dlsym(handle, "hmp_module_entry"));
  if (entry == nullptr) {
    ::dlclose(handle);
    return {nullptr, file + ": not an hmp module (no hmp_module_entry)"};
  }
  const void* backend = entry(abi);
  if (backend == nullptr) {
    ::dlclose(handle);
    return {nullptr, file + ": built for another version of hmp (interface " + std::to_string(abi) +
                         " wanted); reinstall hmp and its modules together"};
  }
  // Never closed: the back-end object and the threads it may have started live as long as the process.
  return {const_cast<void*>(backend), {}};
}

}  // namespace

std::string module_dir() {
  if (const char* dir = std::getenv("HMP_MODULE_DIR"); dir != nullptr && *dir != '\0') return dir;
  return program_dir() + "/../lib/hmp";
}

void* load(const std::string& name, int abi, std::string* why) {
  std::lock_guard lock(g_mutex);
  auto [it, inserted] = slots().try_emplace(name);
  if (inserted) it->second = open_module(name, abi);
  if (why != nullptr) *why = it->second.why;
  return it->second.backend;
}

void* find_loaded(const std::string& name) {
  std::lock_guard lock(g_mutex);
  const auto it = slots().find(name);
  return it == slots().end() ? nullptr : it->second.backend;
}

std::string loaded_summary() {
  std::lock_guard lock(g_mutex);
  std::string out;
  for (const auto& [name, slot] : slots()) {
    if (!out.empty()) out += ", ";
    out += name + (slot.backend != nullptr ? "" : " (unavailable)");
  }
  return out.empty() ? "none" : out;
}

}  // namespace hmp::modules
