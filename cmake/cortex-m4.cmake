# The Cortex-M4F code-generation flags every firmware board of ours uses (STM32F407, the AN386 in QEMU):
# Thumb-2, the single-precision FPU with hard-float calling, one section per function and object so the
# linker drops what is not called; no exceptions, RTTI, thread-safe statics or atexit for C++ (design §8).
set(HMP_CPU_FLAGS "-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16")
set(CMAKE_C_FLAGS_INIT "${HMP_CPU_FLAGS} -ffunction-sections -fdata-sections")
set(CMAKE_CXX_FLAGS_INIT "${HMP_CPU_FLAGS} -ffunction-sections -fdata-sections -fno-exceptions -fno-rtti -fno-threadsafe-statics -fno-use-cxa-atexit")
set(CMAKE_ASM_FLAGS_INIT "${HMP_CPU_FLAGS}")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${HMP_CPU_FLAGS} -Wl,--gc-sections -nostartfiles --specs=nano.specs")
