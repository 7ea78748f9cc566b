// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Place-recognition search over stored descriptors ([SC] = Kim & Kim, IROS 2018, Sec. IV-A):
// the ring keys (rotation-invariant) go into an exact KD-tree; the nearest ring keys are the
// candidates, and the full distance of distance.hpp picks the best of them and its yaw.
//
// Entries are numbered 0, 1, ... in the order of Add (the keyframe index). Build() (re)builds the
// KD-tree over every entry added so far; entries added since the last Build are still searched,
// by brute force over their ring keys, so a query always sees everything added and Build only
// decides the speed. The reference implementation rebuilds its tree every few keyframes; do the
// same (e.g. Build when Pending() exceeds a few hundred).
//
// Thread safety: const members may run concurrently; Add and Build need exclusive access.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include "algorithms/common/status.hpp"
#include "algorithms/scancontext/config.hpp"
#include "algorithms/scancontext/descriptor.hpp"
#include "algorithms/scancontext/distance.hpp"

namespace bimslam::scancontext {

// One ring-key candidate and its full Scan Context distance to the query.
struct Candidate {
    size_t index = 0;                // entry number
    double ring_key_distance = 0.0;  // Euclidean distance between the ring keys
    DistanceResult scan_context;     // Distance(query, entry) (see yaw below)
};

struct Match {
    size_t index = 0;       // the best entry: smallest Scan Context distance among the candidates
    double distance = 0.0;  // its distance, [SC] eq. (6)
    int shift = 0;          // its column shift, see distance.hpp
    // Yaw of the best entry relative to the query with the convention of distance.hpp applied to
    // Distance(query, entry): entry_cloud ~= Rz(yaw) * query_cloud, i.e. yaw is the yaw of
    // T_entry_query, the initial rotation for registering the query scan into the entry's frame.
    double yaw = 0.0;
    // Every candidate, nearest ring key first.
    std::vector<Candidate> candidates;
};

class CandidateIndex {
public:
    // Validates the configuration (throws common::Error). Its shape, num_candidates and
    // search_ratio apply to every entry and query.
    explicit CandidateIndex(const ScanContextConfig& config = ScanContextConfig::Outdoor());
    ~CandidateIndex();
    CandidateIndex(CandidateIndex&&) noexcept;
    CandidateIndex& operator=(CandidateIndex&&) noexcept;
    CandidateIndex(const CandidateIndex&) = delete;
    CandidateIndex& operator=(const CandidateIndex&) = delete;

    // Stores a descriptor; its index is size() - 1 afterwards. kInvalidArgument (nothing stored)
    // when its shape is not rings x sectors of the configuration or a cell is not finite.
    common::Status Add(const Descriptor& descriptor);

    // (Re)builds the KD-tree over all entries on a private contiguous copy of their ring keys, so
    // later Adds never move memory the tree points into. Cheap to call with nothing pending.
    void Build();

    // The best match among the num_candidates entries with the nearest ring keys, leaving out
    // the exclude_recent most recently added entries (intra-session loop search: the previous
    // keyframes always look alike). nullopt ("no match") when no entry is eligible, when the
    // query's shape differs from the configuration's or a cell is not finite, or when
    // num_candidates < 1.
    std::optional<Match> Query(const Descriptor& query, int num_candidates,
                               size_t exclude_recent = 0) const;
    // With config().num_candidates.
    std::optional<Match> Query(const Descriptor& query, size_t exclude_recent = 0) const {
        return Query(query, config_.num_candidates, exclude_recent);
    }

    size_t size() const { return descriptors_.size(); }
    bool empty() const { return descriptors_.empty(); }
    // Entries in the KD-tree, and those added since the last Build.
    size_t Indexed() const { return indexed_; }
    size_t Pending() const { return size() - indexed_; }

    const Descriptor& descriptor(size_t index) const { return descriptors_.at(index); }
    const ScanContextConfig& config() const { return config_; }

private:
    struct Tree;  // FLANN stays out of this header (a private dependency)

    ScanContextConfig config_;
    std::vector<Descriptor> descriptors_;
    std::vector<float> ring_keys_;  // size() x num_rings, row-major; may reallocate on Add
    size_t indexed_ = 0;
    std::unique_ptr<Tree> tree_;
};

}  // namespace bimslam::scancontext
