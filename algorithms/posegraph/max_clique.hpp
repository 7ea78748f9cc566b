// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The maximum clique of an undirected graph: the core of pairwise consistency maximisation
// (Mangelson, Dominic, Eustice, Vasudevan, "Pairwise Consistent Measurement Set Maximization for
// Robust Multi-robot Map Merging", ICRA 2018), where vertices are loop measurements and an edge
// says two loops agree with each other and the odometry.
//
// Exact branch and bound with the greedy-colouring bound of Tomita and Seki ("An efficient
// branch-and-bound algorithm for finding a maximum clique", 2003), on bitsets, after a greedy
// start (Pattabiraman et al. 2015's heuristic: grow a clique from every vertex by highest
// degree) that prunes every vertex of too low a degree. Loop graphs (one large consistent set,
// scattered wrong loops) solve in milliseconds; a step limit bounds pathological inputs, and the
// result then says it is the best found, not proven maximum.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace bimslam::posegraph {

// A symmetric adjacency matrix over n vertices, as bitsets.
class Graph {
public:
    explicit Graph(size_t n);
    void Connect(size_t a, size_t b);
    bool Connected(size_t a, size_t b) const;
    size_t size() const { return n_; }
    size_t Degree(size_t a) const;
    const uint64_t* Row(size_t a) const { return &bits_[a * words_]; }
    size_t words() const { return words_; }

private:
    size_t n_, words_;
    std::vector<uint64_t> bits_;
};

struct CliqueResult {
    std::vector<size_t> vertices;  // ascending
    bool exact = true;             // false: the step limit was hit
    size_t steps = 0;
};

// The largest clique among `allowed` vertices (all when empty).
CliqueResult MaximumClique(const Graph& graph, const std::vector<size_t>& allowed = {},
                           size_t max_steps = 2'000'000);

}  // namespace bimslam::posegraph
