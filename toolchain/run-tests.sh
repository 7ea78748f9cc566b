#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
# `make test` after the set-up: the Release tests, with the clang ASan build compiling beside
# them at the lowest priority (nice 19), then the ASan tests.
#
# Why beside: the Release tests keep about 1.6 of the two cores busy (their processes wait on
# loopback replays, chromium, the disk and each other's cached fixtures: 627 s of CPU in 388 s,
# ctest -j2; -j3 gained 13 s), and the ASan build is pure compiling. At nice 19 the compiler gets
# what the tests leave (CFS weight 15 against 1024), so the tests run much as before while the
# build uses the idle core-time (toolchain/README.md, "Where CI's time goes (stop 51)").
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="${JOBS:-$(nproc)}"

cmake --build --preset release -j "$jobs" --target release_tests
cmake --preset asan >/dev/null
mkdir -p build/asan
log=build/asan/build-beside-tests.log
# setsid: the build gets a process group of its own, so that a failed Release run stops it whole.
setsid nice -n 19 cmake --build --preset asan -j "$jobs" --target sanitizer_tests fuzz_tests \
    >"$log" 2>&1 &
asan_build=$!

release_rc=0
ctest --preset integration -j "$jobs" || release_rc=$?
if [ "$release_rc" -ne 0 ]; then
    kill -- "-$asan_build" 2>/dev/null || true
    wait "$asan_build" 2>/dev/null || true
    echo "run-tests: Release tests failed (ctest exit $release_rc); the ASan build was stopped" >&2
    exit "$release_rc"
fi
echo "run-tests: the ASan build (compiled beside the Release tests, $log):"
asan_rc=0
wait "$asan_build" || asan_rc=$?
cat "$log"
if [ "$asan_rc" -ne 0 ]; then
    echo "run-tests: the ASan build failed (exit $asan_rc), log $log" >&2
    exit "$asan_rc"
fi
ctest --preset asan -j "$jobs"
