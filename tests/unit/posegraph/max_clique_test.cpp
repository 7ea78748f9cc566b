// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The maximum clique against brute force on random graphs, and on a loop-like graph.
#include "algorithms/posegraph/max_clique.hpp"

#include <gtest/gtest.h>

#include <random>

namespace bimslam::posegraph {
namespace {
namespace BIMSLAM_UNITY_ID {

bool IsClique(const Graph& g, const std::vector<size_t>& c) {
    for (size_t i = 0; i < c.size(); ++i) {
        for (size_t j = i + 1; j < c.size(); ++j) {
            if (!g.Connected(c[i], c[j])) return false;
        }
    }
    return true;
}

size_t BruteForce(const Graph& g) {
    size_t best = 0;
    const size_t n = g.size();
    for (uint32_t mask = 1; mask < (1u << n); ++mask) {
        std::vector<size_t> c;
        for (size_t v = 0; v < n; ++v) {
            if (mask & (1u << v)) c.push_back(v);
        }
        if (c.size() > best && IsClique(g, c)) best = c.size();
    }
    return best;
}

TEST(MaximumClique, MatchesBruteForceOnRandomGraphs) {
    std::mt19937 rng(1);
    for (int trial = 0; trial < 60; ++trial) {
        const size_t n = 4 + trial % 13;
        const double p = 0.2 + 0.6 * (trial % 7) / 6.0;
        Graph g(n);
        std::uniform_real_distribution<double> u(0, 1);
        for (size_t a = 0; a < n; ++a) {
            for (size_t b = a + 1; b < n; ++b) {
                if (u(rng) < p) g.Connect(a, b);
            }
        }
        const CliqueResult r = MaximumClique(g);
        EXPECT_TRUE(r.exact);
        EXPECT_TRUE(IsClique(g, r.vertices));
        EXPECT_EQ(r.vertices.size(), BruteForce(g)) << "trial " << trial;
    }
}

TEST(MaximumClique, FindsTheConsistentLoopsAmongWrongOnes) {
    // 300 right loops all consistent with each other, 150 wrong ones consistent with a few.
    const size_t right = 300, wrong = 150;
    Graph g(right + wrong);
    std::mt19937 rng(2);
    std::uniform_int_distribution<size_t> any(0, right + wrong - 1);
    for (size_t a = 0; a < right; ++a) {
        for (size_t b = a + 1; b < right; ++b) g.Connect(a, b);
    }
    for (size_t w = right; w < right + wrong; ++w) {
        for (int k = 0; k < 20; ++k) g.Connect(w, any(rng));
    }
    const CliqueResult r = MaximumClique(g);
    ASSERT_EQ(r.vertices.size(), right);
    EXPECT_EQ(r.vertices.back(), right - 1);
    EXPECT_TRUE(r.exact);
}

TEST(MaximumClique, AllowedLimitsTheVertices) {
    Graph g(5);
    g.Connect(0, 1);
    g.Connect(1, 2);
    g.Connect(0, 2);
    g.Connect(3, 4);
    EXPECT_EQ(MaximumClique(g).vertices, (std::vector<size_t>{0, 1, 2}));
    EXPECT_EQ(MaximumClique(g, {1, 3, 4}).vertices, (std::vector<size_t>{3, 4}));
    EXPECT_TRUE(MaximumClique(Graph(0)).vertices.empty());
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::posegraph
