# stm32f407 tests, included from cmake/cross_tests.cmake: the image as a board or dfu-util takes it.
# (The same image booting under QEMU netduinoplus2 and playing is a host-tree test:
# tests/e2e/play_netduino_test.cpp, which needs hmp.)
add_test(NAME stm32f407_image
  COMMAND ${CMAKE_CURRENT_LIST_DIR}/check_image.sh $<TARGET_FILE:hmp_fw_stm32f407>)
set_tests_properties(stm32f407_image PROPERTIES LABELS firmware TIMEOUT 60 ENVIRONMENT SIZE=${CMAKE_SIZE})
