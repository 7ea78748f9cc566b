// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// g2o pose-graph text files, the subset SC-A-LOAM writes (singlesession_posegraph.g2o):
//   VERTEX_SE3:QUAT id x y z qx qy qz qw
//   EDGE_SE3:QUAT i j x y z qx qy qz qw I11 I12 .. I16 I22 .. I66   (21 upper-triangular entries
//   of the 6x6 information matrix over [x y z rx ry rz])
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "algorithms/io/session.hpp"

namespace bimslam::io {

struct G2oGraph {
    std::vector<Eigen::Isometry3d> vertices;  // vertex i has id i
    std::vector<SessionEdge> edges;
};

std::string SerializeG2o(const G2oGraph& graph);
// One line of it each (SerializeG2o is the vertices' lines, then the edges'): a writer that
// keeps its text appends a line per item instead of formatting the whole graph again.
void AppendG2oVertex(std::string& out, size_t id, const Eigen::Isometry3d& T);
void AppendG2oEdge(std::string& out, const SessionEdge& e);
// Vertices must have ids 0, 1, 2, ... in order, edges must join existing vertices, every number
// must be finite and the information matrix positive semi-definite on its diagonal. Other g2o
// tags (FIX, PARAMS_SE3OFFSET, ...) are rejected: they would change the meaning of the graph.
G2oGraph ParseG2o(const std::string& name, std::string_view text);

}  // namespace bimslam::io
