#pragma once
// host/modules/: the back-ends hmp loads only when a command needs them (design §16). The program itself
// links no library that exists only as a shared object beyond the C library: `hmp info` starts like a
// small C program. Audio (FluidSynth, libsndfile, libsamplerate, SDL2, ALSA), the PNG plots (cairo), USB
// and HID access (hidapi, libusb) and the animation window are modules: shared objects in
// <prefix>/lib/hmp/ beside <prefix>/bin/hmp, opened with dlopen on first use.
//
// A module exports one C function, hmp_module_<name>(abi), returning its back-end object (an abstract
// C++ class declared by the part of hmp that uses it) or null when `abi` is not the one it was built
// for. Nothing throws across the boundary: the back-ends report errors as values. Each module carries
// its own copy of the C++ runtime's shared library (the program links it statically), so objects cross
// only as the plain types of the interfaces (std::string, std::vector, spans), never as exceptions.
//
// A module that cannot be loaded (not installed, a library it needs missing, another build's module) is
// a missing capability, not a failure: load() says why in one line and the caller degrades, e.g. plays
// without sound.
#include <string>

namespace hmp::modules {

// The folder modules are loaded from: $HMP_MODULE_DIR if set, else <folder of the running program>/../lib/hmp.
std::string module_dir();

// The back-end object of module `name` (hmp-<name>.so), loaded on the first call and kept for the life
// of the process. Null when it cannot be had; then `why` (if given) says why, e.g.
// "lib/hmp/hmp-audio.so: libfluidsynth.so.3: cannot open shared object file".
void* load(const std::string& name, int abi, std::string* why = nullptr);

// The back-end of a module loaded before, without loading it: null if it was not (or could not be).
void* find_loaded(const std::string& name);

// The modules loaded so far, for `hmp --version` and tests.
std::string loaded_summary();

// Typed access: `Backend::kModule` names the module and `Backend::kAbi` is its interface version.
template <class Backend>
const Backend* backend(std::string* why = nullptr) {
  return static_cast<const Backend*>(load(Backend::kModule, Backend::kAbi, why));
}

}  // namespace hmp::modules

// What a module defines (in its entry file). `Impl` is a class deriving from the back-end interface.
#define HMP_DEFINE_MODULE(Backend, Impl)                                                    \
  extern "C" __attribute__((visibility("default"))) const void* hmp_module_entry(int abi) { \
    static const Impl instance;                                                             \
    return abi == Backend::kAbi ? static_cast<const Backend*>(&instance) : nullptr;         \
  }
