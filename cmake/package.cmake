# The Debian package (scripts/package; docs/packaging.md): CPack's DEB generator packs what
# cmake/install.cmake installs under /usr. scripts/package computes the dependencies with dpkg-shlibdeps
# (the program's as Depends, the modules' as Recommends) and passes them in.
set(HMP_MAINTAINER "The Haptic Music Player contributors <maintainers@users.noreply.h-seed-81270995.example>")

# Debian's copyright file (machine-readable) with our licence's text from LICENSE, and a changelog entry
# pointing at CHANGELOG.md (a native package's changelog.gz).
file(STRINGS LICENSE license_lines)
set(HMP_LICENSE_TEXT "")
foreach(line IN LISTS license_lines)
  if(line STREQUAL "")
    string(APPEND HMP_LICENSE_TEXT " .\n")
  else()
    string(APPEND HMP_LICENSE_TEXT " ${line}\n")
  endif()
endforeach()
string(STRIP "${HMP_LICENSE_TEXT}" HMP_LICENSE_TEXT)
string(PREPEND HMP_LICENSE_TEXT " ")
set(debian ${PROJECT_BINARY_DIR}/debian)
configure_file(packaging/debian/copyright.in ${debian}/copyright @ONLY)
string(TIMESTAMP HMP_CHANGELOG_DATE "%a, %d %b %Y %H:%M:%S +0000" UTC)  # SOURCE_DATE_EPOCH when set
configure_file(packaging/debian/changelog.in ${debian}/changelog @ONLY)
add_custom_command(OUTPUT ${debian}/changelog.gz
  COMMAND gzip -9nc ${debian}/changelog > ${debian}/changelog.gz
  DEPENDS ${debian}/changelog)
add_custom_target(hmp_debian_changelog ALL DEPENDS ${debian}/changelog.gz)
install(FILES ${debian}/copyright ${debian}/changelog.gz DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/hmp)
# The notices of what is linked in statically (docs/licensing.md), from the Debian packages built against.
foreach(package libcli11-dev libsundials-dev libtomlplusplus-dev nlohmann-json3-dev libfmt-dev libstdc++6
                libnewlib-arm-none-eabi)
  if(EXISTS /usr/share/doc/${package}/copyright)
    install(FILES /usr/share/doc/${package}/copyright DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/hmp/third-party
            RENAME ${package})
  else()
    message(WARNING "/usr/share/doc/${package}/copyright not found: a package would lack its notices")
  endif()
endforeach()
install(FILES packaging/debian/lintian-overrides DESTINATION ${CMAKE_INSTALL_DATADIR}/lintian/overrides RENAME hmp)

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME hmp)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT ${HMP_MAINTAINER})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "haptic music player for SPIDAR-G6 string-based haptic devices")
set(CPACK_PACKAGE_DESCRIPTION
"hmp plays a MIDI song and lets one of its instruments be felt on a SPIDAR-G6
string-based haptic device: every note becomes a vibration whose frequency
and amplitude follow its pitch and whose envelope resembles the instrument's
sound, while the song is heard and its notes scroll past in a window.
.
This package holds the host program, its back-end modules (sound, window,
plots, USB, video), the firmware images for the STM32F407 controller board
and for the emulated qemu-an386 board, the udev rule that gives the user at
the seat access to the board, and example songs. Without the recommended
libraries, hmp info, hmp render to text and hmp play --no-view --no-audio
still work.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # hmp_VERSION_amd64.deb
set(CPACK_DEBIAN_PACKAGE_SECTION sound)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS OFF)  # scripts/package runs dpkg-shlibdeps itself (Depends/Recommends)
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA ${PROJECT_SOURCE_DIR}/packaging/debian/postinst
                                       ${PROJECT_SOURCE_DIR}/packaging/debian/postrm)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_PACKAGE_DIRECTORY ${PROJECT_SOURCE_DIR}/build/package)
include(CPack)
