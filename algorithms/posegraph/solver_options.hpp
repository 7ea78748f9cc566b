// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// How the pose graph (pose_graph.cpp) and the keyframes' refinement against the model
// (algorithms/changes/pose_refinement.cpp) ask Ceres to solve: sparse normal Cholesky (both
// problems are sparse: a pose touches its few edges, loops and points), silent. Included only by
// sources that link Ceres themselves.
#pragma once

#include <ceres/solver.h>

namespace bimslam::posegraph {

inline ceres::Solver::Options SparseSolverOptions(int max_iterations, int threads) {
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    options.max_num_iterations = max_iterations;
    options.num_threads = threads;
    options.logging_type = ceres::SILENT;
    return options;
}

}  // namespace bimslam::posegraph
