# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
# The project's layers and the rules between them (ARCHITECTURE.md, "Layers").
#
# Every library folder declares itself with bimslam_library(); external dependencies that only
# some layers may use are tagged with bimslam_tag_capability(). bimslam_check_layers(), called
# once at the end of the top-level CMakeLists.txt, walks every library's transitive link closure
# and scans its sources for includes, and stops configuration with FATAL_ERROR on a violation:
#
#   algorithms/common        nothing of ours
#   algorithms/*             no LCM, IFC++, Embree; no drivers, firmware, host_tools, lcmtypes
#   algorithms/simulation    the one algorithms library that may use Embree
#   algorithms/pipeline      the one algorithms library that may use drivers: the decoders
#                            drivers/ouster and drivers/can only (not drivers/net)
#   algorithms/changes       may link algorithms/simulation (and so Embree behind its Scene), but
#                            not include Embree: change detection ray-casts through Scene only
#   drivers/*                no LCM, IFC++, Embree; of the algorithms only algorithms/common
#   firmware/*               no IFC++, Embree; no host_tools
#   host_tools/*             no firmware
#   lcmtypes                 LCM only
#
# A library's folder is its path relative to BIMSLAM_ROOT (default: the top source folder), so the
# rules follow the layout and a test can run them on a scratch project.

include_guard(GLOBAL)

if(NOT DEFINED BIMSLAM_ROOT)
    set(BIMSLAM_ROOT "${CMAKE_SOURCE_DIR}")
endif()

# Raw library names and include prefixes that give a capability away even without a tagged target.
set(_bimslam_cap_lcm_names "lcm;liblcm;-llcm;PkgConfig::LCM;bimslam_lcmtypes")
set(_bimslam_cap_lcm_includes "lcm/;bimslam/[a-z0-9_]+_t\\.hpp")
set(_bimslam_cap_ifcpp_names "IfcPlusPlus;ifcplusplus;-lIfcPlusPlus;-lifcplusplus")
set(_bimslam_cap_ifcpp_includes "ifcpp/")
set(_bimslam_cap_embree_names "embree;embree3;-lembree3")
set(_bimslam_cap_embree_includes "embree3/;embree4/")

# Tag an external (imported) target with the capability it grants: lcm, ifcpp or embree.
function(bimslam_tag_capability target capability)
    set_property(TARGET ${target} PROPERTY BIMSLAM_CAPABILITY ${capability})
endfunction()

# bimslam_library(<name> [INTERFACE] SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Creates target bimslam_<name> with alias bimslam::<name>, located in the current folder.
function(bimslam_library name)
    cmake_parse_arguments(ARG "INTERFACE" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
    set(target bimslam_${name})
    if(ARG_INTERFACE)
        add_library(${target} INTERFACE)
        target_link_libraries(${target} INTERFACE ${ARG_PUBLIC_DEPS})
        target_include_directories(${target} INTERFACE "${BIMSLAM_ROOT}")
    else()
        add_library(${target} STATIC ${ARG_SOURCES})
        target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
        target_include_directories(${target} PUBLIC "${BIMSLAM_ROOT}")
        if(COMMAND bimslam_apply_warnings)
            bimslam_apply_warnings(${target})
        endif()
    endif()
    add_library(bimslam::${name} ALIAS ${target})
    file(RELATIVE_PATH folder "${BIMSLAM_ROOT}" "${CMAKE_CURRENT_SOURCE_DIR}")
    set_property(TARGET ${target} PROPERTY BIMSLAM_FOLDER "${folder}")
    set_property(GLOBAL APPEND PROPERTY BIMSLAM_LIBRARIES ${target})
endfunction()

# Collects the transitive link closure of <target> (target names and raw library names).
function(_bimslam_link_closure target out_var)
    set(seen "")
    set(todo ${target})
    while(todo)
        list(POP_FRONT todo item)
        # $<LINK_ONLY:x> and similar wrappers: keep the inner name.
        string(REGEX REPLACE "^\\$<[A-Z_]+:(.*)>$" "\\1" item "${item}")
        if(item STREQUAL "" OR item MATCHES "^\\$<" OR item IN_LIST seen)
            continue()
        endif()
        list(APPEND seen ${item})
        if(TARGET ${item})
            get_target_property(aliased ${item} ALIASED_TARGET)
            if(aliased)
                list(APPEND todo ${aliased})
                continue()
            endif()
            get_target_property(type ${item} TYPE)
            set(deps "")
            if(NOT type STREQUAL "INTERFACE_LIBRARY")
                get_target_property(direct ${item} LINK_LIBRARIES)
                if(direct)
                    list(APPEND deps ${direct})
                endif()
            endif()
            get_target_property(iface ${item} INTERFACE_LINK_LIBRARIES)
            if(iface)
                list(APPEND deps ${iface})
            endif()
            list(APPEND todo ${deps})
        endif()
    endwhile()
    list(REMOVE_ITEM seen ${target})
    set(${out_var} ${seen} PARENT_SCOPE)
endfunction()

# The capabilities a closure entry grants (empty when none).
function(_bimslam_capability_of item out_var)
    set(cap "")
    if(TARGET ${item})
        get_target_property(tag ${item} BIMSLAM_CAPABILITY)
        if(tag)
            set(cap ${tag})
        endif()
    endif()
    foreach(c lcm ifcpp embree)
        if(item IN_LIST _bimslam_cap_${c}_names)
            set(cap ${c})
        endif()
    endforeach()
    set(${out_var} ${cap} PARENT_SCOPE)
endfunction()

# What the folder may not use: capabilities it may not link, capabilities it may not include,
# and folder prefixes of other libraries, with exceptions (folders it may use although a prefix
# forbids them).
function(_bimslam_rules folder caps_var include_caps_var folders_var allowed_var)
    set(caps "")
    set(folders "")
    set(allowed "")
    if(folder STREQUAL "algorithms/common")
        set(caps lcm ifcpp embree)
        set(folders algorithms/ drivers/ firmware/ host_tools/ lcmtypes)
    elseif(folder MATCHES "^algorithms/")
        set(caps lcm ifcpp embree)
        if(folder STREQUAL "algorithms/simulation" OR folder STREQUAL "algorithms/changes")
            set(caps lcm ifcpp)
        endif()
        set(folders drivers/ firmware/ host_tools/ lcmtypes)
        if(folder STREQUAL "algorithms/pipeline")
            # The per-scan join takes the decoders' outputs as they are; never sockets or files.
            set(allowed drivers/ouster drivers/can)
        endif()
    elseif(folder MATCHES "^drivers/")
        set(caps lcm ifcpp embree)
        set(folders algorithms/ firmware/ host_tools/ lcmtypes)
        set(allowed algorithms/common)
    elseif(folder MATCHES "^firmware/")
        set(caps ifcpp embree)
        set(folders host_tools/)
    elseif(folder MATCHES "^host_tools/")
        set(folders firmware/)
    elseif(folder STREQUAL "lcmtypes")
        set(caps ifcpp embree)
        set(folders algorithms/ drivers/ firmware/ host_tools/)
    endif()
    set(include_caps ${caps})
    if(folder STREQUAL "algorithms/changes")
        set(include_caps lcm ifcpp embree)
    endif()
    set(${caps_var} ${caps} PARENT_SCOPE)
    set(${include_caps_var} ${include_caps} PARENT_SCOPE)
    set(${folders_var} ${folders} PARENT_SCOPE)
    set(${allowed_var} ${allowed} PARENT_SCOPE)
endfunction()

# True when `path` (a folder or an include path) starts with one of `prefixes` but with none of
# `allowed`.
function(_bimslam_forbidden path prefixes allowed out_var)
    set(hit FALSE)
    foreach(prefix ${prefixes})
        string(FIND "${path}" "${prefix}" at)
        if(at EQUAL 0)
            set(hit TRUE)
        endif()
    endforeach()
    foreach(ok ${allowed})
        string(FIND "${path}" "${ok}" at)
        if(at EQUAL 0)
            set(hit FALSE)
        endif()
    endforeach()
    set(${out_var} ${hit} PARENT_SCOPE)
endfunction()

function(bimslam_check_layers)
    get_property(libraries GLOBAL PROPERTY BIMSLAM_LIBRARIES)
    set(errors "")
    foreach(lib ${libraries})
        get_target_property(folder ${lib} BIMSLAM_FOLDER)
        _bimslam_rules("${folder}" forbidden_caps forbidden_include_caps forbidden_folders
                       allowed_folders)
        _bimslam_link_closure(${lib} closure)
        foreach(dep ${closure})
            _bimslam_capability_of(${dep} cap)
            if(cap AND cap IN_LIST forbidden_caps)
                list(APPEND errors "${folder} (${lib}) links ${dep}, which brings ${cap}")
            endif()
            if(TARGET ${dep})
                get_target_property(dep_folder ${dep} BIMSLAM_FOLDER)
                if(dep_folder)
                    _bimslam_forbidden("${dep_folder}" "${forbidden_folders}"
                                       "${allowed_folders}" bad)
                    if(bad)
                        list(APPEND errors "${folder} (${lib}) links ${dep} from ${dep_folder}")
                    endif()
                endif()
            endif()
        endforeach()
        # Includes: a header-only use would slip past the link check.
        file(GLOB_RECURSE sources "${BIMSLAM_ROOT}/${folder}/*.hpp" "${BIMSLAM_ROOT}/${folder}/*.h"
             "${BIMSLAM_ROOT}/${folder}/*.cpp")
        set(patterns "")
        foreach(cap ${forbidden_include_caps})
            list(APPEND patterns ${_bimslam_cap_${cap}_includes})
        endforeach()
        foreach(src ${sources})
            file(RELATIVE_PATH rel "${BIMSLAM_ROOT}" "${src}")
            file(STRINGS "${src}" includes REGEX "^[ \t]*#[ \t]*include")
            foreach(line ${includes})
                set(bad FALSE)
                foreach(pattern ${patterns})
                    if(line MATCHES "#[ \t]*include[ \t]*[<\"]${pattern}")
                        set(bad TRUE)
                    endif()
                endforeach()
                # Headers of our other folders, its own folder always allowed.
                if(line MATCHES "#[ \t]*include[ \t]*[<\"]([^>\"]+)[>\"]")
                    _bimslam_forbidden("${CMAKE_MATCH_1}" "${forbidden_folders}"
                                       "${allowed_folders};${folder}/" bad_folder)
                    if(bad_folder)
                        set(bad TRUE)
                    endif()
                endif()
                if(bad)
                    list(APPEND errors "${rel}: '${line}' is not allowed in ${folder}")
                endif()
            endforeach()
        endforeach()
    endforeach()
    if(errors)
        list(JOIN errors "\n  " text)
        message(FATAL_ERROR "Layering violation (see ARCHITECTURE.md, \"Layers\"):\n  ${text}")
    endif()
    list(LENGTH libraries n)
    message(STATUS "bimslam: layering rules hold for ${n} libraries")
endfunction()
