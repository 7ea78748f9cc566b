// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The new objects followed over the visits (internal to the history, map_history.hpp): each
// object found in a visit is matched to the objects known before it, first in place (the same
// object seen again), then by shape (moved: its offset), and the known objects left unmatched
// are gone when the visit saw their place empty, else not observed. The rules and their
// thresholds: HistoryConfig.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "host_tools/mapping/map_history.hpp"

namespace bimslam::mapping {

nlohmann::json Vec(const Eigen::Vector3d& v);
// The same object in place: IoU or centres (HistoryConfig).
bool SamePlace(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b,
               const HistoryConfig& config);
// The share of a's volume inside b grown by margin_m on every side (0 for an empty a).
double InsideShare(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b, double margin_m);
// The same shape (HistoryConfig): the height within the tolerance, and the smallest plan
// rectangles' sides within it too (changes.json's plan_size_m, which a turn about z leaves as
// they are; the boxes' sorted sides in files without it), or else the voxel solids' volumes
// within volume_tolerance (a solid seen from one side is a shell, seen around filled: a sofa
// measured 0.34 and 1.75 m3 with the same box, so the volume only stands in for the plan).
bool SameShape(const change_detection::FoundChanges::Object& a,
               const change_detection::FoundChanges::Object& b, const HistoryConfig& config);
// The same object moved, though its boxes may overlap: its height and plan's sides agree (not the
// volume alone) and its centre is more than same_max_centroid_m away (the centre the offset is
// measured by: the plan rectangle's where the file has it, which a turned object seen in part
// keeps while its box's moves). A whole object seen at two visits keeps its centre to a few
// centimetres; the held-out house's sofa, moved 0.8 m, kept 0.44 of its box's IoU and was "in
// place".
bool Displaced(const change_detection::FoundChanges::Object& a,
               const change_detection::FoundChanges::Object& b, const HistoryConfig& config);

class ObjectTracks {
public:
    explicit ObjectTracks(const HistoryConfig& config) : config_(config) {}

    // Visit v's objects matched to the tracks; returns the objects' part of its changes since
    // the previous visit: {new: [ids], gone: [ids], moved: [{id, offset_m}]}.
    nlohmann::json Update(size_t v, const VisitFindings& visit);
    // The objects not gone after the visits so far: [{id, as_of}] (as_of: last seen).
    nlohmann::json Present(const std::vector<VisitFindings>& visits) const;
    // Every object with its sightings (history.json's "objects").
    nlohmann::json ToJson(const std::vector<VisitFindings>& visits) const;

private:
    struct Track {
        std::string id;
        change_detection::FoundChanges::Object last;  // as it was last seen (box: where)
        std::string storey;
        size_t first_seen = 0, last_seen = 0;  // the visits it was first and last seen in
        std::optional<size_t> gone;            // the visit that saw its place empty
        nlohmann::json sightings = nlohmann::json::array();
    };
    using Pairs = std::vector<std::pair<size_t, size_t>>;  // (track, object)

    std::vector<size_t> Alive() const;
    Pairs InPlace(const std::vector<size_t>& alive, const VisitFindings& visit) const;
    // Objects left unmatched that lie inside a known object's box (HistoryConfig::part_*), each
    // with the track it is a part of; one track may have several parts.
    Pairs Parts(const std::vector<size_t>& alive, const VisitFindings& visit,
                const std::vector<bool>& object_done) const;
    Pairs Moved(const std::vector<size_t>& tracks, const std::vector<size_t>& objects,
                const VisitFindings& visit, const std::vector<double>& seen_empty) const;

    const HistoryConfig& config_;
    std::vector<Track> tracks_;
};

}  // namespace bimslam::mapping
