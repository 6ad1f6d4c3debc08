# What `cmake --install <host tree> --prefix P` puts under P (docs/packaging.md), all found by hmp relative
# to itself (host/common/install_layout.hpp):
#   bin/hmp                          the program (host/CMakeLists.txt)
#   lib/hmp/hmp-*.so                 its modules (host/CMakeLists.txt)
#   share/hmp/examples/              the example songs with their licences
#   share/hmp/firmware/              the stm32f407 .elf/.bin/.dfu and the qemu-an386 image, from the
#                                    cross trees in HMP_FIRMWARE_BUILD_DIR (built before installing)
#   lib/udev/rules.d/70-hmp.rules    access to the board, its DFU bootloader and ST-LINK probes
#   share/man/man1/                  a page per command, generated from the commands' option tables
#   share/bash-completion/completions/hmp   generated from the same tables
#   share/doc/hmp/                   the changelog and the licences of what hmp loads (with
#                                    cmake/package.cmake: copyright, changelog.gz)
include(GNUInstallDirs)

install(FILES examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid examples/bach-bwv1079-trio-sonata-largo.mid
              examples/pedal-demo.mid examples/LICENSE.md examples/LICENSE-ECL-2.0.txt
        DESTINATION ${CMAKE_INSTALL_DATADIR}/hmp/examples)

set(HMP_FIRMWARE_BUILD_DIR ${PROJECT_SOURCE_DIR}/build CACHE PATH
    "Where the cross trees are (<dir>/stm32f407, <dir>/qemu-an386): their images are installed")
set(images
  stm32f407/boards/stm32f407/hmp_fw_stm32f407${HMP_IMAGE_VERSION_SUFFIX}.elf
  stm32f407/boards/stm32f407/hmp_fw_stm32f407${HMP_IMAGE_VERSION_SUFFIX}.bin
  stm32f407/boards/stm32f407/hmp_fw_stm32f407${HMP_IMAGE_VERSION_SUFFIX}.dfu
  qemu-an386/boards/qemu-an386/hmp_fw_qemu_an386${HMP_IMAGE_VERSION_SUFFIX}.elf)
list(TRANSFORM images PREPEND ${HMP_FIRMWARE_BUILD_DIR}/)
foreach(image ${images})
  # An image not built is skipped with a note: the program still works, `hmp flash` then asks for --firmware.
  install(CODE "if(NOT EXISTS \"${image}\")
    message(STATUS \"Not installed (not built; cmake --preset stm32f407|qemu-an386, then --build): ${image}\")
  endif()")
  install(FILES ${image} DESTINATION ${CMAKE_INSTALL_DATADIR}/hmp/firmware OPTIONAL)
endforeach()

install(FILES host/flash/70-hmp.rules DESTINATION lib/udev/rules.d)

# The licence is in copyright (cmake/package.cmake), Debian's place for it.
install(FILES CHANGELOG.md docs/licensing.md DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/hmp)
