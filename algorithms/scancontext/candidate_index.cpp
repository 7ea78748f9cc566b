// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/scancontext/candidate_index.hpp"

#include <flann/algorithms/dist.h>
#include <flann/algorithms/kdtree_single_index.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace bimslam::scancontext {

// The KD-tree and the ring keys it was built on. A FLANN index keeps pointers into the matrix it
// was given, so the keys live here, allocated once per Build and never resized; members are
// destroyed in reverse order, the index before its keys. The single KD-tree is used directly
// rather than through flann::Index, which would instantiate every FLANN algorithm (slow to
// compile).
struct CandidateIndex::Tree {
    std::vector<float> keys;  // rows x cols, row-major
    size_t rows = 0;
    std::unique_ptr<flann::KDTreeSingleIndex<flann::L2<float>>> index;
};

CandidateIndex::CandidateIndex(const ScanContextConfig& config) : config_(config) {
    config_.Validate();
}

CandidateIndex::~CandidateIndex() = default;
CandidateIndex::CandidateIndex(CandidateIndex&&) noexcept = default;
CandidateIndex& CandidateIndex::operator=(CandidateIndex&&) noexcept = default;

common::Status CandidateIndex::Add(const Descriptor& descriptor) {
    if (descriptor.rows() != config_.num_rings || descriptor.cols() != config_.num_sectors) {
        return common::Status(common::StatusCode::kInvalidArgument,
                              "descriptor is " + std::to_string(descriptor.rows()) + " x " +
                                  std::to_string(descriptor.cols()) + ", the index holds " +
                                  std::to_string(config_.num_rings) + " x " +
                                  std::to_string(config_.num_sectors));
    }
    if (!descriptor.allFinite()) {
        return common::Status(common::StatusCode::kInvalidArgument,
                              "descriptor has a non-finite cell");
    }
    const Eigen::VectorXf key = RingKey(descriptor);
    ring_keys_.insert(ring_keys_.end(), key.data(), key.data() + key.size());
    descriptors_.push_back(descriptor);
    return common::Status::Ok();
}

void CandidateIndex::Build() {
    if (tree_ != nullptr && indexed_ == size()) return;
    if (empty()) {
        tree_.reset();
        indexed_ = 0;
        return;
    }
    const auto cols = static_cast<size_t>(config_.num_rings);
    auto tree = std::make_unique<Tree>();
    tree->keys = ring_keys_;  // a contiguous copy that no later Add can move
    tree->rows = size();
    flann::Matrix<float> data(tree->keys.data(), tree->rows, cols);
    // Exact search: a single KD-tree with the default leaf size ([SC] uses an exact tree too).
    tree->index = std::make_unique<flann::KDTreeSingleIndex<flann::L2<float>>>(
        data, flann::KDTreeSingleIndexParams(/*leaf_max_size=*/10));
    tree->index->buildIndex();
    tree_ = std::move(tree);
    indexed_ = tree_->rows;
}

std::optional<Match> CandidateIndex::Query(const Descriptor& query, int num_candidates,
                                           size_t exclude_recent) const {
    if (num_candidates < 1) return std::nullopt;
    if (query.rows() != config_.num_rings || query.cols() != config_.num_sectors ||
        !query.allFinite()) {
        return std::nullopt;
    }
    const size_t n = size();
    const size_t eligible = exclude_recent >= n ? 0 : n - exclude_recent;
    if (eligible == 0) return std::nullopt;
    const size_t k = std::min(static_cast<size_t>(num_candidates), eligible);

    const auto dims = static_cast<size_t>(config_.num_rings);
    Eigen::VectorXf key = RingKey(query);

    // (squared ring-key distance, entry)
    std::vector<std::pair<float, size_t>> found;
    found.reserve(k + (n - indexed_));
    if (tree_ != nullptr && indexed_ > 0) {
        // Excluded entries may sit in the tree: ask for as many more neighbours as there are,
        // so k eligible ones come back whenever the tree holds k.
        const size_t excluded_in_tree = indexed_ > eligible ? indexed_ - eligible : 0;
        const size_t knn = std::min(indexed_, k + excluded_in_tree);
        std::vector<size_t> ids(knn);
        std::vector<float> dists(knn);
        flann::Matrix<float> q(key.data(), 1, dims);
        flann::Matrix<size_t> id_matrix(ids.data(), 1, knn);
        flann::Matrix<float> dist_matrix(dists.data(), 1, knn);
        flann::SearchParams params(/*checks=*/-1, /*eps=*/0.0f, /*sorted=*/true);
        const int got = tree_->index->knnSearch(q, id_matrix, dist_matrix, knn, params);
        for (int i = 0; i < got; ++i) {
            if (ids[i] < eligible) found.emplace_back(dists[i], ids[i]);
        }
    }
    // Entries added since the last Build: brute force over their ring keys.
    for (size_t e = indexed_; e < eligible; ++e) {
        const float* other = ring_keys_.data() + e * dims;
        float d2 = 0.0f;
        for (size_t r = 0; r < dims; ++r) {
            const float diff = key[static_cast<Eigen::Index>(r)] - other[r];
            d2 += diff * diff;
        }
        found.emplace_back(d2, e);
    }
    if (found.empty()) return std::nullopt;
    const size_t keep = std::min(k, found.size());
    std::partial_sort(found.begin(), found.begin() + static_cast<std::ptrdiff_t>(keep),
                      found.end());
    found.resize(keep);

    // [SC] Sec. IV-A: the full distance decides among the ring-key candidates.
    Match match;
    match.candidates.reserve(keep);
    double best = std::numeric_limits<double>::infinity();
    for (const auto& [d2, entry] : found) {
        Candidate c;
        c.index = entry;
        c.ring_key_distance = std::sqrt(static_cast<double>(d2));
        c.scan_context = Distance(query, descriptors_[entry], config_.search_ratio);
        if (c.scan_context.distance < best) {
            best = c.scan_context.distance;
            match.index = entry;
            match.distance = c.scan_context.distance;
            match.shift = c.scan_context.shift;
            match.yaw = c.scan_context.yaw;
        }
        match.candidates.push_back(c);
    }
    return match;
}

}  // namespace bimslam::scancontext
