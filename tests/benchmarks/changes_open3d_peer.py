#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
"""The Open3D peer of changes_benchmark (tests/benchmarks/changes_benchmark.cpp): the same points
against the same mesh, as the paper's Step 3 did it with Open3D: RaycastingScene's
compute_signed_distance for every point, then cluster_dbscan on the points farther than the
threshold. Prints one JSON object; {"skipped": why} when Open3D cannot be imported.

    changes_open3d_peer.py POINTS.npy MESH.ply THRESHOLD_M EPS_M MIN_POINTS [OURS_DISTANCE.npy]
"""
import json
import sys
import time


def main():
    if len(sys.argv) not in (6, 7):
        print(__doc__, file=sys.stderr)
        return 2
    try:
        import numpy as np
        import open3d as o3d
    except ImportError as e:
        print(json.dumps({"skipped": f"{sys.executable} cannot import open3d ({e}): install "
                                     "the Debian package python3-open3d"}))
        return 0
    points_file, mesh_file = sys.argv[1], sys.argv[2]
    threshold, eps, min_points = float(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5])
    points = np.load(points_file).astype(np.float32)
    legacy = o3d.io.read_triangle_mesh(mesh_file)
    mesh = o3d.t.geometry.TriangleMesh.from_legacy(legacy)

    t0 = time.perf_counter()
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(mesh)
    distance = scene.compute_signed_distance(o3d.core.Tensor(points)).numpy()
    t1 = time.perf_counter()
    seeds = points[np.abs(distance) > threshold]
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(seeds.astype(np.float64)))
    labels = np.asarray(cloud.cluster_dbscan(eps=eps, min_points=min_points, print_progress=False))
    t2 = time.perf_counter()

    out = {
        "open3d": o3d.__version__,
        "points": int(points.shape[0]),
        "triangles": int(len(legacy.triangles)),
        "distance_s": t1 - t0,
        "dbscan_s": t2 - t1,
        "total_s": t2 - t0,
        "seeds": int(seeds.shape[0]),
        "clusters": int(labels.max() + 1) if labels.size else 0,
        "noise": int((labels < 0).sum()),
    }
    if len(sys.argv) == 7:
        ours = np.load(sys.argv[6]).astype(np.float64)
        diff = np.abs(np.abs(ours) - np.abs(distance.astype(np.float64)))
        out["max_abs_distance_difference_m"] = float(diff.max())
        # The sign where it means something (points 5 cm or more from every surface): Open3D
        # counts ray crossings, which needs a watertight mesh; ours takes the nearest face's side.
        far = np.abs(ours) >= 0.05
        out["sign_agreement_5cm"] = float(np.mean(np.sign(ours[far]) == np.sign(distance[far])))
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
