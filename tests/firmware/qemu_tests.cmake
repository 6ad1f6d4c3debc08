# Included by tests/CMakeLists.txt for every tests/firmware/qemu_*_test.cpp (executable ${target}): these
# boot the qemu-an386 firmware image, which the cross tree builds (scripts/test builds it first). One
# CTest test per executable, labels realtime and qemu (they pace the emulated board in real time); the tests skip themselves (reported as skipped by
# CTest) when the image or qemu-system-arm is missing. The environment variable HMP_QEMU_ELF overrides the path at run time.
set(HMP_QEMU_ELF "" CACHE FILEPATH "qemu-an386 firmware image the QEMU tests boot (empty: the qemu-an386 preset's)")
set(image ${HMP_QEMU_ELF})
if(NOT image)
  set(image ${PROJECT_SOURCE_DIR}/build/qemu-an386/boards/qemu-an386/hmp_fw_qemu_an386${HMP_IMAGE_VERSION_SUFFIX}.elf)
endif()
target_compile_definitions(${target} PRIVATE HMP_QEMU_ELF="${image}")
add_test(NAME ${target} COMMAND ${target})
# A GTEST_SKIP (no image, no emulator) must show as skipped, not passed: scripts/test fails on skips.
set_tests_properties(${target} PROPERTIES LABELS "realtime;qemu" RUN_SERIAL TRUE TIMEOUT 180
                     SKIP_REGULAR_EXPRESSION "\\[  SKIPPED \\]")
