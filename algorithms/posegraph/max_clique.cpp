// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/posegraph/max_clique.hpp"

#include <algorithm>
#include <bit>

#include "algorithms/common/status.hpp"

namespace bimslam::posegraph {

Graph::Graph(size_t n) : n_(n), words_((n + 63) / 64), bits_(n * words_, 0) {}

void Graph::Connect(size_t a, size_t b) {
    if (a >= n_ || b >= n_) {
        throw common::Error(common::StatusCode::kInvalidArgument, "Graph: vertex out of range");
    }
    if (a == b) return;
    bits_[a * words_ + b / 64] |= uint64_t(1) << (b % 64);
    bits_[b * words_ + a / 64] |= uint64_t(1) << (a % 64);
}

bool Graph::Connected(size_t a, size_t b) const {
    return (bits_[a * words_ + b / 64] >> (b % 64)) & 1u;
}

size_t Graph::Degree(size_t a) const {
    size_t d = 0;
    for (size_t w = 0; w < words_; ++w) d += std::popcount(bits_[a * words_ + w]);
    return d;
}

namespace {

using Bits = std::vector<uint64_t>;

bool Empty(const Bits& b) {
    return std::all_of(b.begin(), b.end(), [](uint64_t w) { return w == 0; });
}
void Reset(Bits& b, size_t v) { b[v / 64] &= ~(uint64_t(1) << (v % 64)); }
bool Test(const Bits& b, size_t v) { return (b[v / 64] >> (v % 64)) & 1u; }
size_t First(const Bits& b) {
    for (size_t w = 0; w < b.size(); ++w) {
        if (b[w]) return w * 64 + size_t(std::countr_zero(b[w]));
    }
    return SIZE_MAX;
}

class Search {
public:
    Search(const Graph& g, size_t max_steps) : g_(g), max_steps_(max_steps) {}

    void Expand(Bits P) {
        if (++steps_ > max_steps_) {
            exact_ = false;
            return;
        }
        // Greedy colouring (Tomita & Seki): vertices in order of their colour class.
        std::vector<size_t> order;
        std::vector<size_t> colour;
        Bits U = P;
        size_t k = 0;
        while (!Empty(U)) {
            ++k;
            Bits Q = U;
            while (!Empty(Q)) {
                const size_t v = First(Q);
                Reset(U, v);
                Reset(Q, v);
                const uint64_t* row = g_.Row(v);
                for (size_t w = 0; w < Q.size(); ++w) Q[w] &= ~row[w];
                order.push_back(v);
                colour.push_back(k);
            }
        }
        for (size_t i = order.size(); i-- > 0;) {
            if (R_.size() + colour[i] <= best_.size() || !exact_) return;
            const size_t v = order[i];
            R_.push_back(v);
            Bits next(P.size());
            const uint64_t* row = g_.Row(v);
            for (size_t w = 0; w < P.size(); ++w) next[w] = P[w] & row[w];
            if (Empty(next)) {
                if (R_.size() > best_.size()) best_ = R_;
            } else {
                Expand(std::move(next));
            }
            R_.pop_back();
            Reset(P, v);
        }
    }

    std::vector<size_t> best_;
    std::vector<size_t> R_;
    size_t steps_ = 0;
    bool exact_ = true;

private:
    const Graph& g_;
    size_t max_steps_;
};

}  // namespace

CliqueResult MaximumClique(const Graph& graph, const std::vector<size_t>& allowed,
                           size_t max_steps) {
    CliqueResult out;
    const size_t n = graph.size();
    Bits A(graph.words(), 0);
    if (allowed.empty()) {
        for (size_t v = 0; v < n; ++v) A[v / 64] |= uint64_t(1) << (v % 64);
    } else {
        for (size_t v : allowed) {
            if (v < n) A[v / 64] |= uint64_t(1) << (v % 64);
        }
    }
    if (Empty(A)) return out;
    // Degrees within the allowed set.
    std::vector<size_t> degree(n, 0), vertices;
    for (size_t v = 0; v < n; ++v) {
        if (!Test(A, v)) continue;
        vertices.push_back(v);
        const uint64_t* row = graph.Row(v);
        for (size_t w = 0; w < A.size(); ++w) degree[v] += std::popcount(row[w] & A[w]);
    }
    std::sort(vertices.begin(), vertices.end(),
              [&](size_t a, size_t b) { return degree[a] > degree[b]; });

    // Greedy start from the 64 vertices of highest degree.
    std::vector<size_t> best{vertices.front()};
    for (size_t s = 0; s < std::min<size_t>(64, vertices.size()); ++s) {
        std::vector<size_t> clique{vertices[s]};
        Bits P(A.size());
        const uint64_t* row = graph.Row(vertices[s]);
        for (size_t w = 0; w < A.size(); ++w) P[w] = A[w] & row[w];
        while (!Empty(P)) {
            size_t pick = SIZE_MAX;
            for (size_t v : vertices) {  // highest degree first
                if (Test(P, v)) {
                    pick = v;
                    break;
                }
            }
            clique.push_back(pick);
            const uint64_t* r = graph.Row(pick);
            for (size_t w = 0; w < P.size(); ++w) P[w] &= r[w];
        }
        if (clique.size() > best.size()) best = clique;
    }
    // Vertices that cannot be in a larger clique go; the exact search runs on the rest.
    Bits P(A.size(), 0);
    for (size_t v : vertices) {
        if (degree[v] + 1 > best.size()) P[v / 64] |= uint64_t(1) << (v % 64);
    }
    Search search(graph, max_steps);
    search.best_ = best;
    if (!Empty(P)) search.Expand(P);
    out.vertices = search.best_;
    std::sort(out.vertices.begin(), out.vertices.end());
    out.exact = search.exact_;
    out.steps = search.steps_;
    return out;
}

}  // namespace bimslam::posegraph
