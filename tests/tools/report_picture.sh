#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
# The README's picture: the top of a report page (summary and the ground floor's plan) rendered by
# headless chromium, scaled down. Usage: tests/tools/report_picture.sh REPORT.html OUT.png
# (e.g. after `make demo`: demo_output/map/report/report.html host_tools/report/report.png).
set -euo pipefail
[[ $# -eq 2 ]] || { echo "usage: $0 REPORT.html OUT.png" >&2; exit 2; }
profile="$(mktemp -d)"
trap 'rm -rf "$profile"' EXIT
chromium --headless --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader \
    --user-data-dir="$profile" --window-size=1400,1080 --force-device-scale-factor=0.65 \
    --virtual-time-budget=3000 --screenshot="$(realpath -m "$2")" "file://$(realpath "$1")" \
    2>/dev/null
echo "wrote $2 ($(stat -c %s "$2") bytes)"
