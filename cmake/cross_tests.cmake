# Tests of a cross (firmware) tree, included by the top-level CMakeLists.txt after the board.
# Boards register their images in the global property HMP_FIRMWARE_IMAGES; board-specific tests
# (e.g. running the image in QEMU) live in boards/<board>/tests.cmake.
get_property(hmp_images GLOBAL PROPERTY HMP_FIRMWARE_IMAGES)
if(NOT hmp_images)
  message(FATAL_ERROR "board ${HMP_BOARD} registered no firmware image (HMP_FIRMWARE_IMAGES)")
endif()

set(hmp_image_files)
foreach(image IN LISTS hmp_images)
  list(APPEND hmp_image_files $<TARGET_FILE:${image}>)
endforeach()

add_test(NAME firmware_no_heap_symbols
  COMMAND ${PROJECT_SOURCE_DIR}/cmake/check_no_heap_symbols.sh ${CMAKE_NM} ${hmp_image_files})
set_tests_properties(firmware_no_heap_symbols PROPERTIES LABELS firmware TIMEOUT 60)

# Every firmware board has its own tests (its image as the board or its emulator takes it).
include(${PROJECT_SOURCE_DIR}/boards/${HMP_BOARD}/tests.cmake)
