// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// SerializeMultiSessionG2o (pose_graph.hpp): the optimised graph for g2o_viewer and LT-mapper.
#include <string>

#include "algorithms/io/file_util.hpp"
#include "algorithms/posegraph/pose_graph.hpp"

namespace bimslam::posegraph {
namespace {

constexpr size_t kSessionIdStride = 1000000;  // LT-mapper's global node index

void AppendPose(std::string& out, const Eigen::Isometry3d& T) {
    const Eigen::Quaterniond q = common::Rotation(T);
    const Eigen::Vector3d t = T.translation();
    for (double v : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) {
        out += ' ';
        out += io::FormatDouble(v);
    }
}

void AppendEdge(std::string& out, size_t a, size_t b, const Eigen::Isometry3d& T,
                const common::Matrix6d& information) {
    out += "EDGE_SE3:QUAT " + std::to_string(a) + " " + std::to_string(b);
    AppendPose(out, T);
    for (int r = 0; r < 6; ++r) {
        for (int c = r; c < 6; ++c) out += " " + io::FormatDouble(information(r, c));
    }
    out += '\n';
}

}  // namespace

std::string SerializeMultiSessionG2o(const PoseGraph& graph) {
    std::string out;
    for (size_t s = 0; s < graph.sessions(); ++s) {
        for (size_t k = 0; k < graph.keyframes(s); ++k) {
            out += "VERTEX_SE3:QUAT " + std::to_string(s * kSessionIdStride + k);
            AppendPose(out, graph.WorldPose(s, k));
            out += '\n';
        }
    }
    for (size_t s = 0; s < graph.sessions(); ++s) {
        if (!graph.fixed(s)) continue;
        for (size_t k = 0; k < graph.keyframes(s); ++k) {
            out += "FIX " + std::to_string(s * kSessionIdStride + k) + "\n";
        }
    }
    for (const OdometryFactor& f : graph.odometry()) {
        AppendEdge(out, f.session * kSessionIdStride + f.from, f.session * kSessionIdStride + f.to,
                   f.T_from_to, f.information);
    }
    for (const LoopFactor& f : graph.loops()) {
        AppendEdge(out, f.session_a * kSessionIdStride + f.index_a,
                   f.session_b * kSessionIdStride + f.index_b, f.T_a_b, f.information);
    }
    return out;
}

}  // namespace bimslam::posegraph
