#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
"""The table of a side-by-side run (side_by_side.sh), one row per scan folder: the APE of both
trajectories against the folder's ground_truth.tum (`bimslam evaluate`, SE(3)-aligned), or for a
folder without ground truth the last pose against the first (a static sensor should not move);
CPU ms per scan p50 / p99 of each tool (median of the repetitions, their range in brackets); the
ratios ours / KISS-ICP within each repetition; the load at the runs' starts.
Usage: BIMSLAM=build/release/bin/bimslam summarise.py WORK_DIR"""
import json
import math
import os
import subprocess
import sys

root = sys.argv[1] if len(sys.argv) > 1 else "."
bimslam = os.environ.get("BIMSLAM", "bimslam")


def evaluate(est, ref):
    r = subprocess.run([bimslam, "evaluate", "--est", est, "--ref", ref, "--json"],
                       capture_output=True, text=True)
    return json.loads(r.stdout) if r.returncode == 0 else None


def end_offset(tum):
    """Translation (m) and rotation angle (deg) of the last pose relative to the first."""
    rows = [list(map(float, l.split()[1:8])) for l in open(tum) if l.strip() and l[0] != "#"]
    (t0, q0), (t1, q1) = (rows[0][:3], rows[0][3:]), (rows[-1][:3], rows[-1][3:])
    # q0^-1 q1 (x y z w): its angle; t0 -> t1 in the first pose's frame has the same norm.
    x0, y0, z0, w0 = q0
    x1, y1, z1, w1 = q1
    w = w0 * w1 + x0 * x1 + y0 * y1 + z0 * z1
    n = math.sqrt(sum(v * v for v in q0)) * math.sqrt(sum(v * v for v in q1))
    angle = math.degrees(2 * math.acos(min(1.0, abs(w) / n)))
    return math.dist(t0, t1), angle


def spread(v, fmt="{:.1f}"):
    v = sorted(v)
    if not v:
        return "-"
    text, lo, hi = fmt.format(v[len(v) // 2]), fmt.format(v[0]), fmt.format(v[-1])
    return text if lo == hi else f"{text} ({lo}-{hi})"


def tool_runs(d, gt, tool):
    r = dict(cpu50=[], cpu99=[], loads=[], ape=[], rot=[], drift=[], end=[], json=[])
    for rep in range(1, 10):
        base = os.path.join(d, f"{tool}_r{rep}")
        if not os.path.exists(base + ".json"):
            continue
        try:
            j = json.load(open(base + ".json"))
        except ValueError:  # a run still writing, or one that failed
            continue
        r["json"].append(j)
        r["cpu50"].append(j["scan_cpu_ms_p50"])
        r["cpu99"].append(j["scan_cpu_ms_p99"])
        r["loads"].append(float(open(base + ".load").read().split()[1]))
        tum = os.path.join(base, "trajectory.tum")
        if os.path.exists(gt):
            e = evaluate(tum, gt)
            if e:
                r["ape"].append(100 * e["ape_trans_rmse_m"])
                r["rot"].append(e["ape_rot_rmse_deg"])
                r["drift"].append(e["drift_percent"])
        else:
            r["end"].append(end_offset(tum))
    return r


def accuracy(t):
    if t["ape"]:
        return (spread(t["ape"], "{:.2f}") + " / " + spread(t["rot"], "{:.2f}") + " / " +
                spread(t["drift"], "{:.2f}"))
    if t["end"]:
        return "end %.1f mm, %.3f deg" % (1000 * max(e[0] for e in t["end"]),
                                          max(e[1] for e in t["end"]))
    return "no match"


print("| folder | ours: APE cm / deg / drift % | KISS-ICP: APE cm / deg / drift % | "
      "ours CPU ms p50 / p99 | KISS-ICP CPU ms p50 / p99 | ours / KISS-ICP p50 / p99 | load |")
print("|---|---|---|---|---|---|---|")
summary = []
for name in sorted(os.listdir(os.path.join(root, "runs"))):
    d = os.path.join(root, "runs", name)
    gt = os.path.join(root, name, "ground_truth.tum")
    o, k = tool_runs(d, gt, "ours"), tool_runs(d, gt, "kiss")
    n = min(len(o["cpu50"]), len(k["cpu50"]))
    r50 = [o["cpu50"][i] / k["cpu50"][i] for i in range(n)]
    r99 = [o["cpu99"][i] / k["cpu99"][i] for i in range(n)]
    loads = o["loads"] + k["loads"]
    print(f"| {name} | {accuracy(o)} | {accuracy(k)} | {spread(o['cpu50'])} / "
          f"{spread(o['cpu99'])} | {spread(k['cpu50'])} / {spread(k['cpu99'])} | "
          f"{spread(r50, '{:.2f}')} / {spread(r99, '{:.2f}')} | "
          f"{min(loads):.1f}-{max(loads):.1f} |")
    oj = o["json"][0] if o["json"] else {}
    summary.append({"folder": name, "ours": {x: o[x] for x in o if x != "json"},
                    "kiss": {x: k[x] for x in k if x != "json"},
                    "ours_flags": {f: oj.get(f) for f in ("degenerate", "failed", "not_converged")},
                    "ours_steps_wall_ms_p50": {f: oj.get(f) for f in (
                        "preprocess_ms_p50", "register_ms_p50", "map_ms_p50")},
                    "ours_registration_points": oj.get("mean_registration_points"),
                    "ours_iterations": oj.get("mean_iterations"),
                    "kiss_registration_points": k["json"][-1].get("mean_registration_points")
                    if k["json"] else None})
json.dump(summary, open(os.path.join(root, "summary.json"), "w"), indent=1)
