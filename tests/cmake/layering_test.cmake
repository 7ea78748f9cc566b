# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
# Proves that configuration fails when a library links or includes a layer it must not
# (toolchain/cmake/BimslamLayers.cmake). Run by ctest as
#   cmake -DTOOLCHAIN_DIR=<repo>/toolchain/cmake -DWORK_DIR=<scratch> -P layering_test.cmake
# Each case is a scratch project laid out like the repository, configured from scratch.
cmake_minimum_required(VERSION 3.25)

set(failures 0)

# case(<name> <PASS|FAIL> <regex expected in the output> <folder=deps;...> [<folder=include>])
#   LIBS: "folder|dep1,dep2" entries; INCLUDES: "folder|header" entries.
function(run_case name expect regex)
    cmake_parse_arguments(ARG "" "" "LIBS;INCLUDES" ${ARGN})
    set(src "${WORK_DIR}/${name}/src")
    file(REMOVE_RECURSE "${WORK_DIR}/${name}")
    set(top "cmake_minimum_required(VERSION 3.25)\nproject(layering_${name} LANGUAGES NONE)\n")
    string(APPEND top "set(BIMSLAM_ROOT \"${src}\")\n")
    string(APPEND top "list(APPEND CMAKE_MODULE_PATH \"${TOOLCHAIN_DIR}\")\n")
    string(APPEND top "include(BimslamLayers)\n")
    foreach(cap lcm ifcpp embree)
        string(APPEND top "add_library(fake_${cap} INTERFACE)\n")
        string(APPEND top "bimslam_tag_capability(fake_${cap} ${cap})\n")
    endforeach()
    foreach(entry ${ARG_LIBS})
        string(REPLACE "|" ";" parts "${entry}")
        list(GET parts 0 folder)
        list(LENGTH parts n)
        set(deps "")
        if(n GREATER 1)
            list(GET parts 1 deps)
            string(REPLACE "," " " deps "${deps}")
        endif()
        string(REPLACE "/" "_" lib "${folder}")
        file(WRITE "${src}/${folder}/CMakeLists.txt"
             "bimslam_library(${lib} INTERFACE PUBLIC_DEPS ${deps})\n")
        file(WRITE "${src}/${folder}/${lib}.hpp" "#pragma once\n")
        string(APPEND top "add_subdirectory(${folder})\n")
    endforeach()
    foreach(entry ${ARG_INCLUDES})
        string(REPLACE "|" ";" parts "${entry}")
        list(GET parts 0 folder)
        list(GET parts 1 header)
        file(APPEND "${src}/${folder}/use.cpp" "#include ${header}\n")
    endforeach()
    string(APPEND top "bimslam_check_layers()\n")
    file(WRITE "${src}/CMakeLists.txt" "${top}")
    execute_process(COMMAND ${CMAKE_COMMAND} -S "${src}" -B "${WORK_DIR}/${name}/build"
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    set(ok TRUE)
    if(expect STREQUAL "PASS" AND NOT rc EQUAL 0)
        set(ok FALSE)
    elseif(expect STREQUAL "FAIL" AND rc EQUAL 0)
        set(ok FALSE)
    elseif(NOT "${out}${err}" MATCHES "${regex}")
        set(ok FALSE)
    endif()
    if(ok)
        message(STATUS "ok   ${name}")
    else()
        message(STATUS "FAIL ${name}: expected ${expect} matching '${regex}', got rc=${rc}\n${out}${err}")
        math(EXPR f "${failures} + 1")
        set(failures ${f} PARENT_SCOPE)
    endif()
endfunction()

set(base "algorithms/common" "drivers/ouster|bimslam::algorithms_common")

run_case(allowed PASS "layering rules hold for 6 libraries"
    LIBS ${base}
         "algorithms/simulation|fake_embree,bimslam::algorithms_common"
         "firmware/app|fake_lcm,bimslam::drivers_ouster"
         "host_tools/bim|fake_ifcpp,fake_embree,fake_lcm,bimslam::algorithms_simulation"
         "lcmtypes|fake_lcm"
    INCLUDES "host_tools/bim|<ifcpp/model/BuildingModel.h>"
             "algorithms/simulation|<embree3/rtcore.h>")
run_case(algorithms_link_lcm FAIL "algorithms/io .*links fake_lcm, which brings lcm"
    LIBS ${base} "algorithms/io|fake_lcm")
run_case(algorithms_link_raw_lcm FAIL "algorithms/io .*links lcm, which brings lcm"
    LIBS ${base} "algorithms/io|lcm")
run_case(algorithms_embree_transitively FAIL "algorithms/odometry .*brings embree"
    LIBS ${base} "algorithms/simulation|fake_embree"
         "algorithms/odometry|bimslam::algorithms_simulation")
run_case(changes_links_simulation PASS "layering rules hold"
    LIBS ${base} "algorithms/simulation|fake_embree"
         "algorithms/changes|bimslam::algorithms_simulation")
run_case(changes_includes_embree FAIL "algorithms/changes/use.cpp: '#include <embree3/rtcore.h>'"
    LIBS ${base} "algorithms/simulation|fake_embree"
         "algorithms/changes|bimslam::algorithms_simulation"
    INCLUDES "algorithms/changes|<embree3/rtcore.h>")
run_case(changes_link_ifcpp FAIL "algorithms/changes .*brings ifcpp"
    LIBS ${base} "algorithms/changes|fake_ifcpp")
run_case(common_links_other_algorithms FAIL "algorithms/common .*links bimslam_algorithms_io"
    LIBS "algorithms/io" "algorithms/common|bimslam::algorithms_io")
run_case(drivers_link_other_algorithms FAIL "drivers/ouster .*links bimslam_algorithms_io"
    LIBS "algorithms/common" "algorithms/io|bimslam::algorithms_common"
         "drivers/ouster|bimslam::algorithms_io")
# The per-scan join may use the decoders, and no other algorithms library may; nor may it use
# drivers/net (sockets, files).
run_case(pipeline_uses_decoders PASS "layering rules hold"
    LIBS ${base} "drivers/can|bimslam::algorithms_common"
         "algorithms/pipeline|bimslam::drivers_ouster,bimslam::drivers_can"
    INCLUDES "algorithms/pipeline|\"drivers/ouster/lidar_frame.hpp\""
             "algorithms/pipeline|\"drivers/can/go1_sample.hpp\"")
run_case(pipeline_links_net FAIL "algorithms/pipeline .*links bimslam_drivers_net"
    LIBS ${base} "drivers/net|bimslam::algorithms_common"
         "algorithms/pipeline|bimslam::drivers_net")
run_case(pipeline_includes_net FAIL "algorithms/pipeline/use.cpp: '#include \"drivers/net/udp_source.hpp\"'"
    LIBS ${base} "algorithms/pipeline"
    INCLUDES "algorithms/pipeline|\"drivers/net/udp_source.hpp\"")
run_case(other_algorithms_link_decoders FAIL "algorithms/odometry .*links bimslam_drivers_ouster"
    LIBS ${base} "algorithms/odometry|bimslam::drivers_ouster")
run_case(firmware_link_ifcpp FAIL "firmware/app .*brings ifcpp"
    LIBS ${base} "firmware/app|fake_ifcpp")
run_case(firmware_link_host_tools FAIL "firmware/app .*links bimslam_host_tools_bim"
    LIBS ${base} "host_tools/bim" "firmware/app|bimslam::host_tools_bim")
run_case(host_tools_link_firmware FAIL "host_tools/cli .*links bimslam_firmware_app"
    LIBS ${base} "firmware/app" "host_tools/cli|bimslam::firmware_app")
run_case(algorithms_include_lcm FAIL "algorithms/common/use.cpp: '#include <lcm/lcm-cpp.hpp>'"
    LIBS ${base} INCLUDES "algorithms/common|<lcm/lcm-cpp.hpp>")
run_case(algorithms_include_generated_message FAIL "use.cpp: '#include <bimslam/odometry_t.hpp>'"
    LIBS ${base} INCLUDES "algorithms/common|<bimslam/odometry_t.hpp>")
run_case(drivers_include_other_algorithms FAIL "drivers/ouster/use.cpp: '#include \"algorithms/io/pcd.hpp\"'"
    LIBS ${base} INCLUDES "drivers/ouster|\"algorithms/common/se3.hpp\""
                          "drivers/ouster|\"algorithms/io/pcd.hpp\"")
run_case(common_includes_itself PASS "layering rules hold"
    LIBS ${base} INCLUDES "algorithms/common|\"algorithms/common/se3.hpp\"")
run_case(drivers_include_firmware FAIL "drivers/ouster/use.cpp"
    LIBS ${base} "firmware/runtime" INCLUDES "drivers/ouster|\"firmware/runtime/queue.hpp\"")
run_case(firmware_include_embree FAIL "firmware/app/use.cpp: '#include <embree3/rtcore.h>'"
    LIBS ${base} "firmware/app" INCLUDES "firmware/app|<embree3/rtcore.h>")

if(failures GREATER 0)
    message(FATAL_ERROR "${failures} layering case(s) failed")
endif()
