#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
"""How late an estimated trajectory's rotation follows the truth's, axis by axis.

    /usr/bin/python3 tests/tools/rotation_lag.py EST.tum REF.tum [--tilt SECONDS]

For each pose of EST (TUM: stamp x y z qx qy qz qw, both in the same body frame), the rotation
error in the body frame, E = log(R_ref^T R0 R_est) with R0 aligning the first second, against the
body's rotation rate from REF (central differences over the neighbouring poses). Both are
high-passed (less their mean over 11 poses), so that the slow drift leaves the fit. Prints per
axis (x, y, z of the body) the slope of E on the rate in ms (a pure delay d gives -d), their
correlation, and E's spread. A delay shared by every axis is a clock's; one axis alone is the
scene's or the motion's (algorithms/odometry/README.md, "How much a stair walk's APE moves").

--tilt SECONDS: instead, the world-frame rotation error (x, y: the tilt; z: the yaw) averaged
over windows of SECONDS, with the truth's heading and height: where the frame's tilt drifts.
"""
import sys

import numpy as np


def load(path):
    d = np.loadtxt(path, ndmin=2)
    return d[:, 0], d[:, 4:8], d[:, 3]


def matrix(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def log_so3(R):
    angle = np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))
    v = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / 2
    return v * (angle / np.sin(angle) if angle > 1e-9 else 1.0)


def high_pass(x, k=11):
    return x - np.array([x[max(0, i - k // 2):i + k // 2 + 1].mean(0) for i in range(len(x))])


def aligned(te, Rr, Re):
    """EST's rotations in REF's world: R0 Re, R0 the rotation nearest to the mean of Rr Re^T over
    the first second (one pose's own error would offset every later one)."""
    first = sum(Rr[i] @ Re[i].T for i in range(len(te)) if te[i] - te[0] < 1.0)
    U, _, Vt = np.linalg.svd(first)
    R0 = U @ np.diag([1, 1, np.linalg.det(U @ Vt)]) @ Vt
    return [R0 @ R for R in Re]


def print_tilt(te, Rr, Re, heights, window_s):
    world = np.array([log_so3(Rr[i] @ Re[i].T) for i in range(len(te))])
    start = 0
    while start < len(te):
        end = start
        while end < len(te) and te[end] - te[start] < window_s:
            end += 1
        e = np.degrees(world[start:end].mean(0))
        heading = np.degrees(np.arctan2(Rr[start][1, 0], Rr[start][0, 0]))
        print("%7.1f s  heading %7.1f deg  z %6.2f m  tilt error x %+.3f y %+.3f deg, yaw %+.3f deg"
              % (te[start] - te[0], heading, heights[start], e[0], e[1], e[2]))
        start = end


def main() -> int:
    tilt = len(sys.argv) == 5 and sys.argv[3] == "--tilt"
    if len(sys.argv) != 3 and not tilt:
        print(__doc__, file=sys.stderr)
        return 2
    te, qe, _ = load(sys.argv[1])
    tr, qr, zr = load(sys.argv[2])
    nearest = np.clip(np.searchsorted(tr, te), 1, len(tr) - 1)
    nearest -= (np.abs(tr[nearest - 1] - te) < np.abs(tr[nearest] - te)).astype(int)
    if len(te) < 30 or np.max(np.abs(tr[nearest] - te)) > 0.005:
        print("rotation_lag: EST and REF need 30 or more common stamps (within 5 ms)",
              file=sys.stderr)
        return 1
    Rr = [matrix(q) for q in qr[nearest]]
    Re = aligned(te, Rr, [matrix(q) for q in qe])
    if tilt:
        print_tilt(te, Rr, Re, zr[nearest], float(sys.argv[4]))
        return 0
    error = np.array([log_so3(Rr[i].T @ Re[i]) for i in range(1, len(te) - 1)])
    rate = np.array([log_so3(Rr[i - 1].T @ Rr[i + 1]) / (te[i + 1] - te[i - 1])
                     for i in range(1, len(te) - 1)])
    error, rate = high_pass(error), high_pass(rate)
    for axis, name in enumerate("xyz"):
        slope = np.polyfit(rate[:, axis], error[:, axis], 1)[0]
        corr = np.corrcoef(rate[:, axis], error[:, axis])[0, 1]
        print("axis %s: slope %+.1f ms, correlation %+.2f, error %.4f deg (std, high-passed)" %
              (name, 1000 * slope, corr, np.degrees(error[:, axis].std())))
    return 0


if __name__ == "__main__":
    sys.exit(main())
