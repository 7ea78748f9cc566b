# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
# Test helpers: one GoogleTest executable per library folder, each test case a ctest entry with
# a label (sanitized, unit, scene, host, integration, data, fuzz) so `ctest -L` picks the sets
# that `make test` runs.
include_guard(GLOBAL)

set_property(GLOBAL PROPERTY BIMSLAM_UNIT_TESTS "")
set_property(GLOBAL PROPERTY BIMSLAM_SANITIZER_TESTS "")
set_property(GLOBAL PROPERTY BIMSLAM_RELEASE_TESTS "")

# bimslam_test(<name> LABEL <label> SOURCES ... DEPS ... [TIMEOUT s] [LOCK resource])
# LOCK: ctest runs no two tests that hold the same resource at once (RESOURCE_LOCK): a test that
# changes the machine (installs packages) holds "machine_packages". Not RUN_SERIAL, which left a
# core idle while DebPackage ran alone (20-28 s): no other test installs, removes or runs what a
# package installs (the other tests run the build's programs, and publish LCM on channels of
# their own).
function(bimslam_test name)
    cmake_parse_arguments(ARG "" "LABEL;TIMEOUT;LOCK" "SOURCES;DEPS" ${ARGN})
    if(NOT ARG_TIMEOUT)
        set(ARG_TIMEOUT 300)
    endif()
    # Under an emulator (the aarch64 tests under qemu-user) a test runs 10 to 200 times slower
    # than natively (Embree's NEON code the most): LidarOdometry.WithEdgeFeatures took 237 s on a
    # loaded machine (all 20 odometry scene tests take 8 s natively), near the 300 s default. The
    # timeout guards against hangs, not a speed goal: three times longer there; no assertion
    # changes.
    if(CMAKE_CROSSCOMPILING_EMULATOR)
        math(EXPR ARG_TIMEOUT "${ARG_TIMEOUT} * 3")
    endif()
    # A firmware-only build (BIMSLAM_HOST_TOOLS=OFF, the aarch64 cross-build) has no host-only
    # library: a test that links one is not built there, and configuration lists it.
    if(NOT BIMSLAM_HOST_TOOLS)
        foreach(dep ${ARG_DEPS})
            if(dep MATCHES "^bimslam::" AND NOT TARGET ${dep})
                set_property(GLOBAL APPEND PROPERTY BIMSLAM_SKIPPED_TESTS "${name} (${dep})")
                return()
            endif()
        endforeach()
    endif()
    add_executable(${name} ${ARG_SOURCES})
    target_link_libraries(${name} PRIVATE ${ARG_DEPS} bimslam::test_support GTest::gtest_main)
    bimslam_apply_warnings(${name})
    # The sources of a test program compile together, in unity batches (one program per label,
    # tests/unit/CMakeLists.txt). Each wraps its anonymous namespace in `namespace
    # BIMSLAM_UNITY_ID`, which CMake defines to a name of its own per source
    # (UNITY_BUILD_UNIQUE_ID), so that two sources' helpers of the same name do not clash;
    # without unity builds (the debug preset) one name serves, each source being alone.
    set_target_properties(${name} PROPERTIES UNITY_BUILD_UNIQUE_ID BIMSLAM_UNITY_ID)
    if(NOT CMAKE_UNITY_BUILD)
        target_compile_definitions(${name} PRIVATE BIMSLAM_UNITY_ID=single_source)
    endif()
    # A test's own sources are glue around the code under test, which keeps its build's
    # optimisation. At -O1 the 25 integration and data test sources took 192 s of CPU against
    # 256 s at -O3 (lcm_test.cpp 7.8 s against 15.4 s); CI time is what this buys.
    # Not -O0 under the sanitizers: it compiled the ASan test programs faster but
    # doubled the unit tests' run time (348 -> 680 s of CPU), since the linker may keep a test
    # object's unoptimised copy of an inline function (Eigen's, the libraries' headers') for
    # the code under test as well (toolchain/README.md, "Build time").
    if(CMAKE_BUILD_TYPE AND NOT CMAKE_BUILD_TYPE STREQUAL "Debug")
        target_compile_options(${name} PRIVATE -O1)
    endif()
    # The project root lets data tests find ../shared/data from any build folder.
    set(lock)
    if(ARG_LOCK)
        set(lock RESOURCE_LOCK ${ARG_LOCK})
    endif()
    gtest_discover_tests(${name}
        DISCOVERY_MODE PRE_TEST
        PROPERTIES LABELS ${ARG_LABEL} TIMEOUT ${ARG_TIMEOUT} ${lock}
                   ENVIRONMENT "BIMSLAM_SOURCE_DIR=${PROJECT_SOURCE_DIR}")
    # Which build a test program belongs to (tests/unit/CMakeLists.txt, toolchain/README.md):
    # `sanitized` ones to the sanitizer run (target sanitizer_tests); the others but fuzz to
    # Release (target release_tests); fuzz (readers_fuzz_test) to target fuzz_tests, run under
    # the sanitizers only. `unit_tests` is the code that runs on the rig, sanitized or not: the
    # aarch64 cross-build builds and runs those. `scene_tests`: the `scene` ones, so that
    # `ctest -L "unit|scene"` after building both targets runs no stale program.
    if(ARG_LABEL STREQUAL "sanitized")
        set_property(GLOBAL APPEND PROPERTY BIMSLAM_SANITIZER_TESTS ${name})
        set_property(GLOBAL APPEND PROPERTY BIMSLAM_UNIT_TESTS ${name})
    elseif(NOT ARG_LABEL STREQUAL "fuzz")
        set_property(GLOBAL APPEND PROPERTY BIMSLAM_RELEASE_TESTS ${name})
        if(ARG_LABEL STREQUAL "unit")
            set_property(GLOBAL APPEND PROPERTY BIMSLAM_UNIT_TESTS ${name})
        elseif(ARG_LABEL STREQUAL "scene")
            set_property(GLOBAL APPEND PROPERTY BIMSLAM_SCENE_TESTS ${name})
        endif()
    endif()
endfunction()

# bimslam_benchmark(<name> SOURCES ... DEPS ...): Google Benchmark executable, label benchmark.
# Not built by default (`make test` runs no benchmark; CI time): `make bench` or the target
# `benchmarks` builds them all.
function(bimslam_benchmark name)
    cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
    add_executable(${name} EXCLUDE_FROM_ALL ${ARG_SOURCES})
    target_link_libraries(${name} PRIVATE ${ARG_DEPS} bimslam::test_support benchmark::benchmark)
    bimslam_apply_warnings(${name})
    add_test(NAME ${name} COMMAND ${name} --benchmark_min_time=0.2)
    set_tests_properties(${name} PROPERTIES LABELS benchmark)
    set_property(GLOBAL APPEND PROPERTY BIMSLAM_BENCHMARKS ${name})
endfunction()
