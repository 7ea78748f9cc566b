// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/g2o.hpp"

#include <cmath>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/text_reader.hpp"

namespace bimslam::io {
namespace {
constexpr const char* kPoseNames[] = {"x", "y", "z", "qx", "qy", "qz", "qw"};

void AppendPose(std::string& out, const Eigen::Isometry3d& T) {
    const Eigen::Quaterniond q = common::Rotation(T);
    const Eigen::Vector3d t = T.translation();
    for (double v : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) {
        out += ' ';
        out += FormatDouble(v);
    }
}

Eigen::Isometry3d ParsePose(const LineReader& r, const std::vector<std::string_view>& tok,
                            size_t first) {
    double v[7];
    for (int i = 0; i < 7; ++i) v[i] = r.ParseDouble(tok[first + i], kPoseNames[i]);
    const Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
    if (std::abs(q.norm() - 1.0) > 1e-3) {
        r.Fail("quaternion norm " + FormatDouble(q.norm()) + " is not 1");
    }
    return common::FromQuaternionTranslation(q, Eigen::Vector3d(v[0], v[1], v[2]));
}
}  // namespace

void AppendG2oVertex(std::string& out, size_t id, const Eigen::Isometry3d& T) {
    out += "VERTEX_SE3:QUAT " + std::to_string(id);
    AppendPose(out, T);
    out += '\n';
}

void AppendG2oEdge(std::string& out, const SessionEdge& e) {
    out += "EDGE_SE3:QUAT " + std::to_string(e.from) + " " + std::to_string(e.to);
    AppendPose(out, e.T_from_to);
    for (int r = 0; r < 6; ++r) {
        for (int c = r; c < 6; ++c) {
            out += ' ';
            out += FormatDouble(e.information(r, c));
        }
    }
    out += '\n';
}

std::string SerializeG2o(const G2oGraph& graph) {
    std::string out;
    for (size_t i = 0; i < graph.vertices.size(); ++i) AppendG2oVertex(out, i, graph.vertices[i]);
    for (const SessionEdge& e : graph.edges) AppendG2oEdge(out, e);
    return out;
}

G2oGraph ParseG2o(const std::string& name, std::string_view text) {
    LineReader r(name, text);
    G2oGraph g;
    std::vector<std::string_view> tok;
    std::string_view line;
    while (r.Next(line)) {
        LineReader::Split(line, tok);
        if (tok.empty()) continue;
        if (tok[0] == "VERTEX_SE3:QUAT") {
            if (tok.size() != 9) {
                r.Fail("VERTEX_SE3:QUAT needs an id and 7 numbers, found " +
                       std::to_string(tok.size() - 1) + " values");
            }
            const int64_t id = r.ParseInt(tok[1], "vertex id");
            if (id != static_cast<int64_t>(g.vertices.size())) {
                r.Fail("vertex id " + std::to_string(id) + " out of order; expected " +
                       std::to_string(g.vertices.size()));
            }
            g.vertices.push_back(ParsePose(r, tok, 2));
        } else if (tok[0] == "EDGE_SE3:QUAT") {
            if (tok.size() != 31) {
                r.Fail(
                    "EDGE_SE3:QUAT needs 2 ids, 7 pose numbers and 21 information entries, "
                    "found " +
                    std::to_string(tok.size() - 1) + " values");
            }
            SessionEdge e;
            const int64_t from = r.ParseInt(tok[1], "edge from"),
                          to = r.ParseInt(tok[2], "edge to");
            const auto n = static_cast<int64_t>(g.vertices.size());
            if (from < 0 || to < 0 || from >= n || to >= n || from == to) {
                r.Fail("edge " + std::to_string(from) + " -> " + std::to_string(to) +
                       " does not join two of the " + std::to_string(n) + " vertices above it");
            }
            e.from = static_cast<uint32_t>(from);
            e.to = static_cast<uint32_t>(to);
            e.T_from_to = ParsePose(r, tok, 3);
            size_t k = 10;
            for (int row = 0; row < 6; ++row) {
                for (int col = row; col < 6; ++col) {
                    const double v = r.ParseDouble(tok[k++], "information(" + std::to_string(row) +
                                                                 "," + std::to_string(col) + ")");
                    e.information(row, col) = v;
                    e.information(col, row) = v;
                }
                if (e.information(row, row) < 0.0) {
                    r.Fail("information(" + std::to_string(row) + "," + std::to_string(row) +
                           ") is negative");
                }
            }
            g.edges.push_back(e);
        } else if (tok[0].front() != '#') {
            r.Fail("unsupported g2o tag '" + std::string(tok[0].substr(0, 40)) + "'");
        }
    }
    return g;
}

}  // namespace bimslam::io
