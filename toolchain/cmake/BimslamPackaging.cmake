# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
# Debian packages with CPack (`make deb`; toolchain/debian/README.md):
#   bimslam-rig    component `rig`: bimslam-rig and bimslam-go1-bridge, their systemd units,
#                  example configurations in /etc/bimslam (conffiles), the system user `bimslam`
#                  and /var/lib/bimslam/sessions (postinst); for the architecture built for.
#   bimslam-tools  component `tools`: the host tool `bimslam` (not in a firmware-only build).
# Dependencies come from the shared libraries the programs link (dpkg-shlibdeps).
include(GNUInstallDirs)

# `make deb` packages what the Release build has: installing must not build every target (the
# tests) first, only what the components hold (Makefile, target deb).
set(CMAKE_SKIP_INSTALL_ALL_DEPENDENCY ON)

set(_debian "${PROJECT_SOURCE_DIR}/toolchain/debian")

# Documentation every package carries: the copyright file and a compressed changelog (lintian
# errors without them); gzip -n so the package is the same bytes from one build to the next.
set(_changelog "${PROJECT_BINARY_DIR}/packaging/changelog.Debian.gz")
file(MAKE_DIRECTORY "${PROJECT_BINARY_DIR}/packaging")
execute_process(COMMAND gzip -9 -n -c "${_debian}/changelog" OUTPUT_FILE "${_changelog}"
                RESULT_VARIABLE _gzip)
if(NOT _gzip EQUAL 0)
    message(FATAL_ERROR "gzip ${_debian}/changelog failed: ${_gzip}")
endif()

# bimslam_package_docs(component package [files...]): copyright, changelog and `files` into
# /usr/share/doc/<package>.
function(bimslam_package_docs component package)
    set(dir "${CMAKE_INSTALL_DATADIR}/doc/${package}")
    install(FILES "${_debian}/copyright" "${_changelog}" ${ARGN} DESTINATION "${dir}"
            COMPONENT ${component})
endfunction()

# The rig: programs, units, configurations. Absolute paths where the units name them.
install(TARGETS bimslam-rig bimslam-go1-bridge RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}"
        COMPONENT rig)
install(FILES "${PROJECT_SOURCE_DIR}/firmware/app/systemd/bimslam-rig.service"
              "${PROJECT_SOURCE_DIR}/firmware/go1_bridge/systemd/bimslam-go1-bridge.service"
        DESTINATION /lib/systemd/system COMPONENT rig)
install(FILES "${PROJECT_SOURCE_DIR}/firmware/app/config/go1.yaml" DESTINATION /etc/bimslam
        RENAME rig.yaml COMPONENT rig)
install(FILES "${PROJECT_SOURCE_DIR}/firmware/app/config/handheld.yaml"
              "${PROJECT_SOURCE_DIR}/firmware/go1_bridge/systemd/go1-bridge.conf"
        DESTINATION /etc/bimslam COMPONENT rig)
install(FILES "${PROJECT_SOURCE_DIR}/firmware/go1_bridge/README.md"
        DESTINATION "${CMAKE_INSTALL_DATADIR}/doc/bimslam-rig" RENAME go1_bridge.md COMPONENT rig)
bimslam_package_docs(rig bimslam-rig "${PROJECT_SOURCE_DIR}/firmware/app/README.md")
set(_components rig)
set(_contents bimslam-rig bimslam-go1-bridge)

if(BIMSLAM_HOST_TOOLS)
    install(TARGETS bimslam RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}" COMPONENT tools)
    # The LCM types for lcm-spy on the laptop (lcmtypes/README.md), when a JDK built them.
    if(TARGET bimslam_lcmtypes_jar)
        install(FILES "${PROJECT_BINARY_DIR}/lcmtypes/bimslam_lcmtypes.jar"
                DESTINATION "${CMAKE_INSTALL_DATADIR}/java" RENAME bimslam-lcmtypes.jar
                COMPONENT tools)
        list(APPEND _contents bimslam_lcmtypes_jar)
    endif()
    bimslam_package_docs(tools bimslam-tools)
    list(APPEND _components tools)
    list(APPEND _contents bimslam)
endif()
# What the packages hold, built by `make deb` (and the package test) before cpack, and nothing else.
add_custom_target(deb_contents DEPENDS ${_contents})

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME bimslam)
set(CPACK_PACKAGE_VENDOR "bimslam")
set(CPACK_PACKAGE_CONTACT "bimslam developers <bimslam@example.org>")
set(CPACK_PACKAGE_VERSION "${PROJECT_VERSION}")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_PACKAGE_DIRECTORY "${PROJECT_BINARY_DIR}/packages")
set(CPACK_STRIP_FILES ON)
set(CPACK_COMPONENTS_ALL ${_components})
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_RELEASE 1)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# Maintainer scripts 0755, conffiles 0644, whatever the checkout's modes.
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
if(CMAKE_CROSSCOMPILING AND CMAKE_SYSTEM_PROCESSOR STREQUAL "aarch64")
    set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE arm64)
    # dpkg-shlibdeps for arm64 (`make deb-arm64`, toolchain/README.md). DEB_HOST_ARCH makes it
    # search /usr/lib/aarch64-linux-gnu and read the programs with aarch64-linux-gnu-objdump; it is
    # set in cpack's own environment by a file cpack reads when it runs. The staged libraries
    # (toolchain/stage-arm64.sh) are found through -l (CPack's "private dirs"); dpkg knows no
    # package for them, so dpkg-shlibdeps takes their dependency (libceres3, liblcm1, ...) from
    # the shlibs and symbols files in the staging's DEBIAN/, the nearest above each library.
    set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS
        "${BIMSLAM_ARM64_STAGING}/usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}")
    set(CPACK_PROJECT_CONFIG_FILE "${PROJECT_BINARY_DIR}/packaging/cpack_arm64.cmake")
    file(WRITE "${CPACK_PROJECT_CONFIG_FILE}" "set(ENV{DEB_HOST_ARCH} arm64)\n")
endif()

set(CPACK_DEBIAN_RIG_PACKAGE_NAME bimslam-rig)
set(CPACK_DEBIAN_RIG_PACKAGE_DEPENDS adduser)  # postinst; the libraries come from shlibdeps
set(CPACK_DEBIAN_RIG_PACKAGE_CONTROL_EXTRA "${_debian}/bimslam-rig/conffiles"
    "${_debian}/bimslam-rig/postinst" "${_debian}/bimslam-rig/prerm"
    "${_debian}/bimslam-rig/postrm")
# Lines of at most 80 characters (lintian).
set(CPACK_COMPONENT_RIG_DESCRIPTION
    "on-board LiDAR mapping firmware for buildings with a BIM model
bimslam-rig reads an Ouster OS1 LiDAR and the Unitree Go1's state over CAN,
runs LiDAR odometry and keyframing in bounded time, publishes on LCM and
records sessions under /var/lib/bimslam/sessions. bimslam-go1-bridge turns
the Go1's UDP HighState into the CAN frames the rig reads. Both run as
systemd services under the system user bimslam.")

set(CPACK_DEBIAN_TOOLS_PACKAGE_NAME bimslam-tools)
# IFC++'s libraries have no version in their names (libIfcPlusPlus.so) and its package no shlibs
# file, so dpkg-shlibdeps cannot map them to a package: named here.
set(CPACK_DEBIAN_TOOLS_PACKAGE_DEPENDS libifcplusplus)
set(CPACK_COMPONENT_TOOLS_DESCRIPTION
    "host tool for LiDAR mapping against a BIM (IFC) model
bimslam turns an IFC model into a reference session, simulates captures, runs
the odometry offline, anchors recorded sessions to the model, detects changes
and writes an HTML report.")

include(CPack)
