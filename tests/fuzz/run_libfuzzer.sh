#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
# Runs one libFuzzer target for BIMSLAM_FUZZ_SECONDS (default 15) over a scratch copy of its seed
# corpus, so ctest runs it briefly and `make fuzz` longer. A crash leaves crash-* in the work
# folder, named in the output; reproduce with `<target> <crash file>`.
set -euo pipefail
target=$1
seeds=${2:-}
work=$3
seconds=${BIMSLAM_FUZZ_SECONDS:-15}
rm -rf "$work" && mkdir -p "$work/corpus"
if [[ -n "$seeds" && -d "$seeds" ]]; then cp -r "$seeds"/. "$work/corpus/"; fi
cd "$work"
exec "$target" corpus -max_total_time="$seconds" -max_len=70000 -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1
