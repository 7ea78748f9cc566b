// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Test helpers for the sample buildings' IFC files: a small reader of the generator's own STEP
// output (one entity a line) and the surfaces of elements read back by IFC++, compared by distance
// (IFC++ triangulates the same surface differently from run to run). Used by
// sample_building_test.cpp and sample_layouts_test.cpp.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "host_tools/bim/bim_model.hpp"

namespace bimslam::bim {

// ---- a small reader of our own STEP output: one entity a line ------------------------------
struct Token {
    enum Kind { kRef, kString, kReal, kInteger, kOther } kind;
    std::string text;
};
struct Entity {
    std::string cls;
    std::vector<Token> args;  // flattened: nesting ignored
};

inline std::vector<Token> Tokenize(const std::string& s) {
    std::vector<Token> out;
    for (size_t i = 0; i < s.size();) {
        const char c = s[i];
        if (c == '\'') {
            std::string text;
            for (++i; i < s.size(); ++i) {
                if (s[i] == '\'' && i + 1 < s.size() && s[i + 1] == '\'') {
                    text += '\'';
                    ++i;
                } else if (s[i] == '\'') {
                    break;
                } else {
                    text += s[i];
                }
            }
            ++i;
            out.push_back({Token::kString, text});
        } else if (c == '#') {
            size_t j = i + 1;
            while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j;
            out.push_back({Token::kRef, s.substr(i + 1, j - i - 1)});
            i = j;
        } else if (std::isdigit(static_cast<unsigned char>(c)) || c == '-') {
            size_t j = i + 1;
            while (j < s.size() && (std::isdigit(static_cast<unsigned char>(s[j])) || s[j] == '.' ||
                                    s[j] == 'E' || s[j] == '-' || s[j] == '+')) {
                ++j;
            }
            const std::string text = s.substr(i, j - i);
            out.push_back(
                {text.find('.') != std::string::npos ? Token::kReal : Token::kInteger, text});
            i = j;
        } else if (c == '.' || std::isalpha(static_cast<unsigned char>(c)) || c == '$' ||
                   c == '*') {
            size_t j = i + 1;
            while (j < s.size() && s[j] != ',' && s[j] != ')' && s[j] != '(') ++j;
            out.push_back({Token::kOther, s.substr(i, j - i)});
            i = j;
        } else {
            ++i;  // ( ) ,
        }
    }
    return out;
}

// id -> entity, in file order.
inline std::map<int, Entity> ParseData(const std::string& text) {
    std::map<int, Entity> out;
    const size_t data = text.find("\nDATA;\n");
    EXPECT_NE(data, std::string::npos);
    size_t pos = data + 7;
    while (pos < text.size()) {
        const size_t end = text.find('\n', pos);
        const std::string line = text.substr(pos, end - pos);
        pos = end + 1;
        if (line == "ENDSEC;") break;
        EXPECT_EQ(line.front(), '#') << line;
        EXPECT_EQ(line.substr(line.size() - 2), ");") << line;
        const size_t eq = line.find('='), open = line.find('(');
        const int id = std::stoi(line.substr(1, eq - 1));
        EXPECT_EQ(out.count(id), 0u) << "entity #" << id << " defined twice";
        out[id] = {line.substr(eq + 1, open - eq - 1),
                   Tokenize(line.substr(open + 1, line.size() - open - 3))};
    }
    return out;
}

inline size_t CountClass(const std::map<int, Entity>& data, const std::string& cls) {
    return size_t(std::count_if(data.begin(), data.end(),
                                [&](const auto& e) { return e.second.cls == cls; }));
}

// Distance from p to the triangle abc (Ericson, Real-Time Collision Detection, 5.1.5).
inline double PointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                    const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return (p - a).norm();
    const Eigen::Vector3d bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return (p - b).norm();
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + ab * (d1 / (d1 - d3)))).norm();
    const Eigen::Vector3d cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return (p - c).norm();
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + ac * (d2 / (d2 - d6)))).norm();
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        return (p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))))).norm();
    }
    const double denom = 1.0 / (va + vb + vc);
    return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

struct ElementMesh {
    std::vector<Eigen::Vector3d> vertices;  // of its triangles
    std::vector<std::array<Eigen::Vector3d, 3>> triangles;
    double area = 0;
    Eigen::AlignedBox3d box;
};

inline ElementMesh MeshOf(const BimModel& m, const BimElement& e) {
    ElementMesh out;
    std::set<uint32_t> used;
    for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
        std::array<Eigen::Vector3d, 3> tri;
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = m.mesh.triangles[t][k];
            tri[k] = m.mesh.vertices[v].cast<double>() + m.origin_m;
            if (used.insert(v).second) out.vertices.push_back(tri[k]);
            out.box.extend(tri[k]);
        }
        out.area += 0.5 * (tri[1] - tri[0]).cross(tri[2] - tri[0]).norm();
        out.triangles.push_back(tri);
    }
    return out;
}

// The largest distance from a vertex of `a` to the surface of `b`.
inline double OneSidedDistance(const ElementMesh& a, const ElementMesh& b) {
    double worst = 0;
    for (const Eigen::Vector3d& p : a.vertices) {
        double best = INFINITY;
        for (const auto& t : b.triangles) {
            best = std::min(best, PointTriangleDistance(p, t[0], t[1], t[2]));
            if (best < 1e-6) break;
        }
        worst = std::max(worst, best);
    }
    return worst;
}

}  // namespace bimslam::bim
