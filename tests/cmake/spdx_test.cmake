# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
# Every source the project wrote and tracks in git starts with its licence (README.md, "Licence"):
# after a shebang, a Python coding line or the HTML doctype, if any, the two lines
#   <comment> SPDX-License-Identifier: BSD-3-Clause
#   <comment> SPDX-FileCopyrightText: <year> The bimslam authors
# in the file's own comment syntax (//, #, /* */, <!-- -->). Names every file that lacks them.
# Run by ctest as
#   cmake -DSOURCE_DIR=<repo> -P spdx_test.cmake
# Which files: git's list (what the project tracks, not build folders or scratch files). Outside
# a git checkout it prints SKIPPED (ctest counts the test as skipped).
cmake_minimum_required(VERSION 3.25)

# Sources by name. Data, JSON, Markdown and files with no comment syntax are not sources here:
# the DBC (its bytes are embedded and parsed), dpkg's conffiles and changelog, the copyright file.
set(source_patterns
    "[.](cpp|hpp|h|c|cpp[.]in|js|mjs|lcm|css|html|cmake|sh|py|yaml|service|conf)$"
    "(^|/)CMakeLists[.]txt$"
    "^Makefile$"
    "^[.]ci/run$"
    "^toolchain/debian/bimslam-rig/(postinst|prerm|postrm)$")
# Not the project's words: seed inputs of the fuzz targets, and anything npm installs.
set(excluded_patterns "^tests/fuzz/corpus/" "(^|/)node_modules/")

set(c "(//|#|/[*]|<!--)")
set(end "( [*]/| -->)?")
set(year "[0-9][0-9][0-9][0-9](-[0-9][0-9][0-9][0-9])?")
set(header_regex "^(#![^\n]*\n|<!DOCTYPE[^\n]*\n)?(# -[*]- coding[^\n]*\n)?")
string(APPEND header_regex "${c} SPDX-License-Identifier: BSD-3-Clause${end}\n")
string(APPEND header_regex "${c} SPDX-FileCopyrightText: ${year} The bimslam authors${end}\n")

find_program(GIT_EXECUTABLE git)
if(GIT_EXECUTABLE)
    execute_process(COMMAND "${GIT_EXECUTABLE}" -C "${SOURCE_DIR}" ls-files
                    RESULT_VARIABLE rc OUTPUT_VARIABLE tracked ERROR_VARIABLE err)
endif()
if(NOT GIT_EXECUTABLE OR NOT rc EQUAL 0)
    message("SKIPPED: no git list of the project's files in ${SOURCE_DIR} ${err}")
    return()
endif()
string(REPLACE "\n" ";" tracked "${tracked}")

set(checked 0)
set(missing "")
foreach(path IN LISTS tracked)
    set(is_source FALSE)
    foreach(pattern IN LISTS source_patterns)
        if(path MATCHES "${pattern}")
            set(is_source TRUE)
        endif()
    endforeach()
    foreach(pattern IN LISTS excluded_patterns)
        if(path MATCHES "${pattern}")
            set(is_source FALSE)
        endif()
    endforeach()
    if(NOT is_source OR NOT EXISTS "${SOURCE_DIR}/${path}")
        continue()
    endif()
    math(EXPR checked "${checked} + 1")
    file(READ "${SOURCE_DIR}/${path}" head LIMIT 512)
    if(NOT head MATCHES "${header_regex}")
        list(APPEND missing "${path}")
    endif()
endforeach()

if(checked EQUAL 0)
    message(FATAL_ERROR "no source matched the patterns in ${SOURCE_DIR}: the test is broken")
endif()
list(LENGTH missing n)
if(n GREATER 0)
    foreach(path IN LISTS missing)
        message("no SPDX header: ${path}")
    endforeach()
    message(FATAL_ERROR
        "${n} of ${checked} sources lack the SPDX header. Make these their first comment lines "
        "(after a shebang or doctype), in the file's comment syntax:\n"
        "  // SPDX-License-Identifier: BSD-3-Clause\n"
        "  // SPDX-FileCopyrightText: <year> The bimslam authors")
endif()
message("SPDX headers in all ${checked} sources")
