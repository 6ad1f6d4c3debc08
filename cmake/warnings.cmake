# Warnings for our own code only (third-party headers come in as SYSTEM includes).
add_library(hmp_warnings INTERFACE)
target_compile_options(hmp_warnings INTERFACE
  -Wall -Wextra -Werror -Wshadow -Wconversion -Wno-sign-conversion -Wdouble-promotion
  $<$<COMPILE_LANGUAGE:CXX>:-Wold-style-cast -Wnon-virtual-dtor>)

# Freestanding rules for shared/ and firmware/: no exceptions, no RTTI, no heap, no OS.
add_library(hmp_freestanding INTERFACE)
target_compile_options(hmp_freestanding INTERFACE
  $<$<COMPILE_LANGUAGE:CXX>:-fno-exceptions -fno-rtti -fno-threadsafe-statics>)
