#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
"""How closely a simulated capture's trajectory follows the treads of the flights it walked.

usage: flight_height_error.py MODEL.ifc CAPTURE_DIR go1|handheld [BIMSLAM]

For every frame whose base (ground_truth.tum's sensor pose times capture.json's T_base_sensor
inverted) stands within an eighth of a run of a tread's centre along the flight (and 0.3 m across
it), the error is base z - the platform's base height (Go1 0.32 m, handheld 1.2 m) - the tread's
height, the treads as `bimslam bim stairs --json` reads them from the model. Prints the largest,
the 95th percentile and the mean. Pure Python (no numpy)."""
import json
import math
import subprocess
import sys


def rotation(qx, qy, qz, qw):
    return [[1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
            [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
            [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]]


def main():
    model, capture, platform = sys.argv[1:4]
    bimslam = sys.argv[4] if len(sys.argv) > 4 else "bimslam"
    graph = json.loads(subprocess.run([bimslam, "bim", "stairs", "--json", "--platform", platform,
                                       model], capture_output=True, text=True).stdout)
    manifest = json.load(open(capture + "/capture.json"))
    m = manifest["sensor"]["T_base_sensor"]  # row-major 4x4
    R_bs = [m[0:3], m[4:7], m[8:11]]
    t_bs = [m[3], m[7], m[11]]
    # T_sensor_base = inverse(T_base_sensor): translation -R^T t.
    t_sb = [-sum(R_bs[r][c] * t_bs[r] for r in range(3)) for c in range(3)]
    base_height = 0.32 if platform == "go1" else 1.2
    bases = []
    for line in open(capture + "/ground_truth.tum"):
        if line.startswith("#"):
            continue
        _, x, y, z, qx, qy, qz, qw = map(float, line.split())
        R = rotation(qx, qy, qz, qw)
        bases.append([(x, y, z)[r] + sum(R[r][c] * t_sb[c] for c in range(3)) for r in range(3)])
    errors, levels = [], 0
    for f in graph["flights"]:
        if not f["walkable"]:
            continue
        centres = [l["centre"] for l in f["levels"]]
        levels += len(centres)
        for k, c in enumerate(centres):
            a, b = centres[max(k - 1, 0)], centres[min(k + 1, len(centres) - 1)]
            ux, uy = b[0] - a[0], b[1] - a[1]
            n = math.hypot(ux, uy)
            if n < 1e-6:
                continue
            ux, uy = ux / n, uy / n
            for p in bases:
                dx, dy = p[0] - c[0], p[1] - c[1]
                if abs(dx * ux + dy * uy) > f["run_m"] / 8 or abs(dx * uy - dy * ux) > 0.3:
                    continue
                error = abs(p[2] - base_height - c[2])
                if error < 0.5:  # not a pass over the flight on another storey
                    errors.append(error)
    if not errors:
        print(f"{capture}: no frame over a tread")
        return
    errors.sort()
    p95 = errors[min(len(errors) - 1, int(0.95 * len(errors)))]
    print(f"{capture}: {len(errors)} frames over the {levels} levels of the walkable flights: "
          f"height error max {100 * errors[-1]:.2f} cm, p95 {100 * p95:.2f} cm, "
          f"mean {100 * sum(errors) / len(errors):.2f} cm")


if __name__ == "__main__":
    main()
