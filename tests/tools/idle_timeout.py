#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
"""Runs a command and stops it early when it hangs: like timeout(1), but a command whose processes
together used less than a tenth of one core over the last IDLE seconds is stopped too.

    python3 tests/tools/idle_timeout.py IDLE LIMIT COMMAND [ARG...]

Exits with the command's status, or 124 when it was stopped (idle for IDLE s, or running for
LIMIT s), as timeout(1) does; says which on stderr.

Why. Headless chromium now and then never ends a --virtual-time-budget run
(tests/integration/headless_chromium.hpp): a clean-clone run at stop 80 had one of its eight page
runs hang, and timeout(1)'s bound of 100 s (three times the longest run) cost 70 s more than the
run it replaced. Traced once a second (70 runs of the visits page, two at a time, stop 80), a
page at work kept chromium's processes at 0.6-1.5 s of CPU every second, and the run that hung
worked 23 s, then used 0.03-0.04 s a second until stopped at 100 s, without writing the DOM.

How. The command runs in a session of its own; every process of that session (chromium's
renderer and GPU processes too) counts, with the CPU of the children they reaped (/proc/PID/stat:
utime, stime, cutime, cstime). Stopping sends SIGTERM to every process of that session, then
SIGKILL.
"""
import collections
import os
import signal
import subprocess
import sys
import time

IDLE_SHARE = 0.1  # of one core
POLL_S = 0.5


def session_stats(sid: int):
    """(pid, the /proc/PID/stat fields after "pid (comm) ") of every process in session `sid`."""
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open(f"/proc/{pid}/stat", encoding="ascii", errors="replace") as f:
                stat = f.read()
        except OSError:  # gone meanwhile
            continue
        fields = stat[stat.rfind(")") + 2:].split()
        if int(fields[3]) == sid:  # field 6, session
            yield int(pid), fields


def session_cpu_s(sid: int) -> float:
    """CPU seconds of every live process in session `sid`, with their reaped children's."""
    ticks = 0
    for _, fields in session_stats(sid):
        ticks += sum(int(x) for x in fields[11:15])  # fields 14-17: utime stime cutime cstime
    return ticks / os.sysconf("SC_CLK_TCK")


def stop(proc: subprocess.Popen) -> None:
    """SIGTERM, then SIGKILL, to every process of the command's session: the ones counted, also
    those in a process group of their own, which killpg would miss."""
    for sig in (signal.SIGTERM, signal.SIGKILL):
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline:
            live = [pid for pid, fields in session_stats(proc.pid) if fields[0] != "Z"]
            if not live:
                break
            for pid in live:
                try:
                    os.kill(pid, sig)
                except ProcessLookupError:
                    pass
            proc.poll()  # reaps the command itself once it ends
            time.sleep(0.1)
    proc.wait()


def main() -> int:
    if len(sys.argv) < 4:
        print(__doc__, file=sys.stderr)
        return 125
    idle_s, limit_s = float(sys.argv[1]), float(sys.argv[2])
    proc = subprocess.Popen(sys.argv[3:], start_new_session=True)
    start = time.monotonic()
    samples = collections.deque([(start, 0.0)])  # (time, CPU s) over the last idle_s
    while True:
        try:
            return proc.wait(timeout=POLL_S)
        except subprocess.TimeoutExpired:
            pass
        now, cpu = time.monotonic(), session_cpu_s(proc.pid)
        samples.append((now, cpu))
        while len(samples) > 1 and samples[1][0] <= now - idle_s:
            samples.popleft()
        then, cpu_then = samples[0]
        reason = None
        if now - then >= idle_s and cpu - cpu_then < IDLE_SHARE * (now - then):
            reason = f"idle: {cpu - cpu_then:.2f} s of CPU in the last {now - then:.1f} s"
        elif now - start >= limit_s:
            reason = f"still running after {limit_s:g} s"
        if reason:
            print(f"idle_timeout: stopped {sys.argv[3]} ({reason}; {cpu:.1f} s of CPU in "
                  f"{now - start:.1f} s)", file=sys.stderr, flush=True)
            stop(proc)
            return 124


if __name__ == "__main__":
    sys.exit(main())
