// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// How much of each change the walk saw (issue 31, item 8): for every added object and every
// removed or moved element, the beams that hit its surface over the whole capture.
//   added objects and moved elements: the returns whose element id is theirs (the scene holds
//     them where they are);
//   removed elements: they are not in the scene, so their own geometry (as the model has it) is
//     cast along the same beams, noiseless, and a beam counts where it would have hit the removed
//     element before what it did hit (or where it had no return).
// A change no beam hit cannot be found by any change detection. Written into changes.json as
// `beam_hits`. Every scan counts here, while change detection maps only the keyframes (one scan in
// about ten): the scores' "in view" is what the keyframes put on an object (the run's map), and
// beam_hits only says, of those out of view, which no beam saw at all
// (host_tools/changes/change_evaluation.hpp).
#pragma once

#include <Eigen/Geometry>
#include <map>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <span>
#include <string>
#include <vector>

#include "algorithms/simulation/lidar_model.hpp"
#include "algorithms/simulation/lidar_simulator.hpp"
#include "algorithms/simulation/scene.hpp"
#include "host_tools/bim/bim_model.hpp"
#include "host_tools/simulate/world.hpp"

namespace bimslam::simulate {

// What a walk of several visits asks of each walk beyond its own changes (visits.hpp), counted the
// same way and reported by key, not in changes.json:
//   absent: things not in this world (an earlier visit's object now gone), cast along the beams as
//     removed elements are: a beam counts where it would have hit the thing before what it hit;
//   elements: elements of the model by GlobalId (one rebuilt since an earlier visit): the
//     returns on them.
struct HitWatch {
    std::map<std::string, common::TriangleMesh> absent;
    std::vector<std::string> elements;
};

class BeamHitCounter {
public:
    BeamHitCounter(const bim::BimModel& model, const World& world, const HitWatch& watch = {});

    // One frame: `image` as simulated from the per-column poses.
    void Count(const simulation::LidarModel& lidar, std::span<const Eigen::Isometry3d> poses,
               const simulation::ScanImage& image);

    // Adds `beam_hits` to each entry of changes.json's added, removed and moved lists.
    void AddTo(nlohmann::json& changes) const;

    size_t HitsOfAdded(size_t k) const;
    size_t HitsOfElement(const std::string& global_id) const;
    // The hits on what the HitWatch named, by its key (absent) or GlobalId (elements).
    std::map<std::string, size_t> Watched() const;

private:
    std::vector<size_t> added_hits_;
    std::map<uint32_t, size_t> element_hits_;      // by element index: removed and moved ones
    std::map<uint32_t, std::string> element_ids_;  // element index -> GlobalId (the changed)
    std::unique_ptr<simulation::Scene> removed_;   // the removed elements' own geometry
    simulation::ScanImage removed_image_;
    std::vector<std::string> absent_keys_;  // HitWatch::absent, by scene id
    std::vector<size_t> absent_hits_;
    std::vector<std::string> watched_elements_;
    std::unique_ptr<simulation::Scene> absent_;
};

}  // namespace bimslam::simulate
