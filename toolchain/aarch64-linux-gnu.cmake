# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
# Cross-compilation to 64-bit ARM Linux (the Go1's Jetson, a Raspberry Pi class board) with
# Debian's cross compiler (crossbuild-essential-arm64) and arm64 multiarch packages of the
# dependencies; `toolchain/install-deps.sh --cross` installs both (toolchain/README.md).
# Used by the `aarch64` preset: firmware only (BIMSLAM_HOST_TOOLS=OFF), the unit tests run under
# qemu-user as CMake's cross-compiling emulator, so ctest runs them unchanged.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
# Debian multiarch: the target's libraries are in /usr/lib/aarch64-linux-gnu, its headers in
# /usr/include (shared by all architectures), so there is no separate sysroot.
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

# Ceres (through glog/gflags), LCM and yaml-cpp: their arm64 -dev packages cannot be installed
# beside the amd64 ones (same files, not Multi-Arch: same), so install-deps.sh unpacks the arm64
# packages into this staging folder instead (toolchain/README.md, "Cross-build").
set(BIMSLAM_ARM64_STAGING "/opt/bimslam-cross/arm64" CACHE PATH
    "Where toolchain/install-deps.sh --cross unpacks the arm64 packages that cannot be installed")
set(_staging_lib "${BIMSLAM_ARM64_STAGING}/usr/lib/aarch64-linux-gnu")
if(NOT EXISTS "${_staging_lib}/libceres.so")
    message(FATAL_ERROR "No arm64 staging in ${BIMSLAM_ARM64_STAGING} "
                        "(run: sudo toolchain/install-deps.sh --cross)")
endif()
list(APPEND CMAKE_PREFIX_PATH "${BIMSLAM_ARM64_STAGING}/usr")
# The staged libraries' own dependencies (libceres -> libglog -> libgflags) for the linker.
string(APPEND CMAKE_EXE_LINKER_FLAGS_INIT " -Wl,-rpath-link,${_staging_lib}")
string(APPEND CMAKE_SHARED_LINKER_FLAGS_INIT " -Wl,-rpath-link,${_staging_lib}")

# pkg-config for the target (Debian's wrapper reads the arm64 .pc files), and the staged ones.
set(PKG_CONFIG_EXECUTABLE aarch64-linux-gnu-pkg-config CACHE FILEPATH "pkg-config for aarch64")
set(ENV{PKG_CONFIG_PATH} "${_staging_lib}/pkgconfig")

# Programs (lcm-gen, qemu) are the build machine's; libraries, headers and packages the target's.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)

# The tests run under qemu-user. Its aarch64 loader is Debian's (libc6:arm64, /lib); -E sets,
# for the emulated program only:
# - LD_LIBRARY_PATH: the staged libraries;
# - CMAKE_PREFIX_PATH: where pluginlib looks for the ROS bag library's encryption plugin
#   (<prefix>/lib/librosbag_default_encryption_plugins.so; stage-arm64.sh links ros/lib to it).
#   Installed, it is in /usr/lib/aarch64-linux-gnu/ros, pluginlib's default, not in the staging;
# - BIMSLAM_EMULATOR: tests::Emulator() (tests/support), for what qemu-user cannot do.
find_program(BIMSLAM_QEMU_AARCH64 qemu-aarch64-static qemu-aarch64)
if(BIMSLAM_QEMU_AARCH64)
    set(CMAKE_CROSSCOMPILING_EMULATOR
        "${BIMSLAM_QEMU_AARCH64};-E;LD_LIBRARY_PATH=${_staging_lib}"
        "-E;CMAKE_PREFIX_PATH=${BIMSLAM_ARM64_STAGING}/ros;-E;BIMSLAM_EMULATOR=qemu-aarch64")
endif()
