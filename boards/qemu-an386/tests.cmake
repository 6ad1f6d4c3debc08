# qemu-an386 tests, included from cmake/cross_tests.cmake.
add_test(NAME qemu_boot_one_note
  COMMAND ${CMAKE_CURRENT_LIST_DIR}/check_one_note.sh $<TARGET_FILE:hmp_fw_qemu_an386_demo>)
set_tests_properties(qemu_boot_one_note PROPERTIES LABELS "firmware;qemu" TIMEOUT 60)

add_test(NAME qemu_boot_firmware
  COMMAND ${CMAKE_CURRENT_LIST_DIR}/check_firmware_boot.sh $<TARGET_FILE:hmp_fw_qemu_an386>)
set_tests_properties(qemu_boot_firmware PROPERTIES LABELS "firmware;qemu" TIMEOUT 60)

# The tick's instruction budgets (design §8): counted, not timed, so they hold on a busy machine too.
add_test(NAME qemu_tick_budgets
  COMMAND ${CMAKE_CURRENT_LIST_DIR}/check_tick_budgets.sh ${PROJECT_SOURCE_DIR} ${CMAKE_BINARY_DIR})
set_tests_properties(qemu_tick_budgets PROPERTIES LABELS "firmware;qemu" TIMEOUT 300)
