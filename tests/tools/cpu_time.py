#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
"""CPU time of a command's whole process tree, for figures that a shared machine's load would
blur in wall time (a test's chromium run, a fixture's commands).

    python3 tests/tools/cpu_time.py LABEL COMMAND [ARG...]

prints `LABEL: rc N, wall W s, cpu C s`. The script makes itself the children's subreaper
(prctl PR_SET_CHILD_SUBREAPER), so processes that outlive their parent (chromium's renderer and
GPU processes) are reaped here and counted by getrusage(RUSAGE_CHILDREN) too; /usr/bin/time
counts only the descendants their own parents waited for. The command's output is discarded.
"""
import ctypes
import os
import resource
import subprocess
import sys
import time

PR_SET_CHILD_SUBREAPER = 36


def main() -> int:
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    ctypes.CDLL(None, use_errno=True).prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0)
    start = time.monotonic()
    proc = subprocess.Popen(sys.argv[2:], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    rc = proc.wait()
    while True:  # the orphans, now ours
        try:
            os.wait()
        except ChildProcessError:
            break
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    print(f"{sys.argv[1]}: rc {rc}, wall {time.monotonic() - start:.1f} s, "
          f"cpu {usage.ru_utime + usage.ru_stime:.1f} s", flush=True)
    return rc


if __name__ == "__main__":
    sys.exit(main())
