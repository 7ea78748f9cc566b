#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
# Says how much disk the build and the temporary directory have before the tests or the demo run,
# and warns when it is short: the rig writes no keyframe while its disk has less than
# session.min_free_mb (1 GB) free, so every test that reads a rig's session then fails on "no
# keyframes" (a CI run at stop 67 failed 13 tests so). A warning, not a failure: the tests and the
# demo say what they could not do.
set -euo pipefail
want_gb=${1:-4}
for dir in . "${TMPDIR:-/tmp}"; do
    free_kb=$(df -Pk "$dir" | awk 'NR==2 {print $4}')
    free_gb=$((free_kb / 1024 / 1024))
    if ((free_gb < want_gb)); then
        echo "check-disk: WARNING: $(realpath "$dir") has ${free_gb} GB free, under the ${want_gb} GB" \
            "the tests and the demo need; below 1 GB the rig writes no keyframe (session.min_free_mb)" >&2
    else
        echo "check-disk: $(realpath "$dir") has ${free_gb} GB free"
    fi
done
