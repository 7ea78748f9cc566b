#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
"""Runs a command and stops it early when it hangs idle: like timeout(1), but a command whose
processes together used less than 0.1 s of CPU over IDLE seconds is stopped too.

    python3 tests/tools/idle_timeout.py IDLE LIMIT COMMAND [ARG...]

Exits with the command's status, or 124 when it was stopped (idle for IDLE s, or running for
LIMIT s), as timeout(1) does; says which on stderr.

Why. Headless chromium now and then never ends a --virtual-time-budget run and sits idle
(tests/integration/headless_chromium.hpp); a clean-clone run at stop 80 had one of its eight
page runs hang, and timeout(1)'s bound of 100 s (three times the longest run) cost 70 s more than
the run it replaced. A running page keeps chromium busy (virtual time runs only while it works),
so a run with no CPU for IDLE seconds has hung.

How. The command runs in a session of its own; every process of that session (chromium's
renderer and GPU processes too) counts, with the CPU of the children they reaped (/proc/PID/stat:
utime, stime, cutime, cstime). Stopping sends SIGTERM to the session, then SIGKILL 5 s later.
"""
import os
import signal
import subprocess
import sys
import time

IDLE_CPU_S = 0.1
POLL_S = 0.5


def session_cpu_s(sid: int) -> float:
    """CPU seconds of every live process in session `sid`, with their reaped children's."""
    ticks = 0
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open(f"/proc/{pid}/stat", encoding="ascii", errors="replace") as f:
                stat = f.read()
        except OSError:  # gone meanwhile
            continue
        fields = stat[stat.rfind(")") + 2:].split()  # after "pid (comm) "
        if int(fields[3]) != sid:  # field 6, session
            continue
        ticks += sum(int(x) for x in fields[11:15])  # fields 14-17: utime stime cutime cstime
    return ticks / os.sysconf("SC_CLK_TCK")


def stop(proc: subprocess.Popen) -> None:
    for sig, wait in ((signal.SIGTERM, 5), (signal.SIGKILL, 5)):
        try:
            os.killpg(proc.pid, sig)
        except ProcessLookupError:
            return
        try:
            proc.wait(timeout=wait)
            return
        except subprocess.TimeoutExpired:
            pass


def main() -> int:
    if len(sys.argv) < 4:
        print(__doc__, file=sys.stderr)
        return 125
    idle_s, limit_s = float(sys.argv[1]), float(sys.argv[2])
    proc = subprocess.Popen(sys.argv[3:], start_new_session=True)
    start = time.monotonic()
    last_cpu, last_busy = 0.0, start
    while True:
        try:
            return proc.wait(timeout=POLL_S)
        except subprocess.TimeoutExpired:
            pass
        now = time.monotonic()
        cpu = session_cpu_s(proc.pid)
        if cpu - last_cpu >= IDLE_CPU_S:
            last_cpu, last_busy = cpu, now
        reason = None
        if now - last_busy >= idle_s:
            reason = f"idle: {cpu - last_cpu:.2f} s of CPU in the last {now - last_busy:.1f} s"
        elif now - start >= limit_s:
            reason = f"still running after {limit_s:g} s"
        if reason:
            print(f"idle_timeout: stopped {sys.argv[3]} ({reason}; {cpu:.1f} s of CPU in "
                  f"{now - start:.1f} s)", file=sys.stderr, flush=True)
            stop(proc)
            return 124


if __name__ == "__main__":
    sys.exit(main())
