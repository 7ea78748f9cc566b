# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
# kiss_icp_peer on a 3 s simulated Go1 walk, exported as `bimslam ouster export --all` writes it:
# one pose per scan stamped at the sweep's end, KISS-ICP on one thread (the process's CPU time is
# the registrations'), a trajectory that matches the ground truth within 20 cm (measured 5 cm),
# and exit 2 on a folder without scans. Run by ctest (kiss_icp_peer_runs) with -DBIMSLAM=...
# -DPEER=... -DWORK_DIR=...
function(run)
    execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "${ARGN}: exit ${rc}\n${out}${err}")
    endif()
    set(out "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
run(${BIMSLAM} bim sample -o ${WORK_DIR}/office.ifc)
run(${BIMSLAM} simulate --model ${WORK_DIR}/office.ifc --duration 3 --seed 1 -o ${WORK_DIR}/cap)
run(${BIMSLAM} ouster export ${WORK_DIR}/cap --all -o ${WORK_DIR}/scans)
run(${PEER} ${WORK_DIR}/scans -o ${WORK_DIR}/kiss --json)
set(summary "${out}")

file(STRINGS "${WORK_DIR}/scans/times.txt" times)
file(STRINGS "${WORK_DIR}/kiss/trajectory.tum" poses)
list(LENGTH times n_times)
list(LENGTH poses n_poses)
string(JSON scans GET "${summary}" scans)
string(JSON threads GET "${summary}" threads)
string(JSON cpu_sum GET "${summary}" scan_cpu_ms_sum)
string(JSON process_cpu GET "${summary}" process_cpu_ms)
if(NOT scans EQUAL n_times OR NOT n_poses EQUAL n_times OR n_times LESS 20)
    message(FATAL_ERROR "${n_times} scans in times.txt, ${scans} run, ${n_poses} poses written")
endif()
if(NOT threads EQUAL 1)
    message(FATAL_ERROR "KISS-ICP configured with ${threads} threads, not 1")
endif()
# Other threads' work would show as process time beyond the registrations' (+10 % and 50 ms
# for the loop's own bookkeeping).
string(REGEX REPLACE "\\..*" "" cpu_sum_ms "${cpu_sum}")
math(EXPR limit "${cpu_sum_ms} * 11 / 10 + 50")
if(process_cpu GREATER limit)
    message(FATAL_ERROR "process CPU ${process_cpu} ms against ${cpu_sum} ms on the thread")
endif()
# The first pose at the first sweep's end: the scan start plus about 0.1 s (1024x10).
list(GET times 0 t0)
list(GET poses 0 first)
string(REGEX MATCH "^[0-9.]+" s0 "${first}")
string(REGEX REPLACE "^([0-9]+)\\.([0-9][0-9][0-9]).*" "\\1\\2" t0_ms "${t0}")
string(REGEX REPLACE "^([0-9]+)\\.([0-9][0-9][0-9]).*" "\\1\\2" s0_ms "${s0}")
math(EXPR dt_ms "${s0_ms} - ${t0_ms}")
if(dt_ms LESS 95 OR dt_ms GREATER 100)
    message(FATAL_ERROR "first pose stamped ${s0}, scan start ${t0}: not the sweep's end")
endif()
run(${BIMSLAM} evaluate --est ${WORK_DIR}/kiss/trajectory.tum
    --ref ${WORK_DIR}/scans/ground_truth.tum --json)
string(JSON ape GET "${out}" ape_trans_rmse_m)
string(JSON matched GET "${out}" matched)
if(NOT ape LESS 0.2 OR matched LESS 20)
    message(FATAL_ERROR "APE ${ape} m over ${matched} poses")
endif()
message(STATUS "kiss_icp_peer: ${scans} scans, APE ${ape} m, CPU ${cpu_sum} ms in all")

file(MAKE_DIRECTORY "${WORK_DIR}/empty")
execute_process(COMMAND ${PEER} ${WORK_DIR}/empty -o ${WORK_DIR}/x RESULT_VARIABLE rc
                ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "empty")
    message(FATAL_ERROR "an empty folder: exit ${rc}, '${err}' (expected 2 naming the folder)")
endif()
file(REMOVE_RECURSE "${WORK_DIR}")
