# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
# Compiler settings shared by every target of the project.
include_guard(GLOBAL)

set(CMAKE_CXX_STANDARD 20)
set(CMAKE_CXX_STANDARD_REQUIRED ON)
set(CMAKE_CXX_EXTENSIONS OFF)
set(CMAKE_POSITION_INDEPENDENT_CODE ON)

option(BIMSLAM_WERROR "Treat warnings as errors" ON)
set(BIMSLAM_SANITIZE "" CACHE STRING "Sanitizers to build with, e.g. address,undefined")

# GCC collects the garbage of its own heap from 4 x its RAM-derived minimum (about 128 MB) on:
# a unity batch of Eigen and Ceres code grows to 1-1.7 GB and was collected over and over.
# Collecting from 1 GB, and then at 4 x growth, took 14 % off algorithms/odometry's batch (47.9 ->
# 41.2 s) for a quarter more memory (1.34 -> 1.68 GB); toolchain/README.md, "Where CI's time goes
# (stop 46)".
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    add_compile_options(--param=ggc-min-expand=400 --param=ggc-min-heapsize=1048576)
endif()

if(BIMSLAM_SANITIZE)
    # Everything, dependencies' inline code included, is built with the sanitizers; a report stops
    # the test instead of scrolling past.
    add_compile_options(-fsanitize=${BIMSLAM_SANITIZE} -fno-omit-frame-pointer
                        -fno-sanitize-recover=all)
    add_link_options(-fsanitize=${BIMSLAM_SANITIZE})
endif()

# Applied to the project's own targets only (not to generated or third-party code).
# Not -Wnull-dereference: GCC 12 reports it falsely inside libstdc++ and FLANN once inlined.
function(bimslam_apply_warnings target)
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow
                           -Wnon-virtual-dtor -Wcast-align -Wunused -Woverloaded-virtual
                           -Wimplicit-fallthrough)
    # GCC 12 reports false -Wrestrict on std::string concatenation at -O2/-O3 (GCC bug 105651).
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
        target_compile_options(${target} PRIVATE -Wno-restrict)
    endif()
    if(BIMSLAM_WERROR)
        target_compile_options(${target} PRIVATE -Werror)
    endif()
endfunction()

# --version of the programs: the project's version and the processor it was built for (aarch64
# in the cross-build), so that a copied binary says what it is.
function(bimslam_version_definitions target)
    target_compile_definitions(${target} PRIVATE BIMSLAM_VERSION="${PROJECT_VERSION}"
                               BIMSLAM_ARCH="${CMAKE_SYSTEM_PROCESSOR}")
endfunction()
