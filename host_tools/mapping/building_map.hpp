// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The building's map in BIM coordinates over its visits (issue 33, item 5; README.md of this
// folder, "The building's map"): one point per 5 cm voxel holding the current state, with the
// visits that first and last saw it. Each visit's map (its recordings' map_bim.ply) is folded in
// in date order:
// - its points refresh the voxels they fall in (class, position, last visit) or add new ones;
//   transients (points where other keyframes looked through) never enter;
// - the voxels its history supersedes are dropped: those of an object gone or moved (inside its
//   old box), and those of an element newly missing (map_bim.ply's scalar_element);
// - a voxel no later visit saw, and nothing contradicted, stays, as of the visit that last saw it.
// So its size follows the building, not the number of visits; the figures per visit say so.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <unordered_map>
#include <vector>

#include "host_tools/mapping/map_history.hpp"

namespace bimslam::mapping {

class BuildingMap {
public:
    explicit BuildingMap(double voxel_m = 0.05, double supersede_m = 0.15)
        : voxel_(voxel_m), supersede_m_(supersede_m) {}

    // Folds in visit v (visits in date order, v = 0, 1, ...); `history` is BuildHistory's value
    // over the same visits. Returns the visit's figures: {visit, voxels, added, refreshed,
    // dropped: {superseded_objects, missing_elements}, transient_points}.
    nlohmann::json Add(size_t v, const VisitFindings& visit, const nlohmann::json& history);

    size_t size() const { return voxels_.size(); }
    double voxel_m() const { return voxel_; }
    double supersede_m() const { return supersede_m_; }
    // Writes the map as a binary PLY: x y z (the model file's coordinates, metres), scalar_class
    // (map_bim.ply's), scalar_first_visit and scalar_last_visit (indices into the visits),
    // scalar_element (map_bim.ply's: the model element a point lies on, -1 none).
    void Write(const std::filesystem::path& file) const;
    // Reads a map Write wrote, in place of this one's voxels; false when the file lacks a
    // property Write writes (an older layout). Throws common::FileError on a damaged file.
    bool Read(const std::filesystem::path& file);
    // The same voxels as ASPRS LAS 1.4 (host_tools/changes/map_las.hpp's classes; README.md of
    // this folder): point source id the 1-based visit that last saw the voxel, GPS time that
    // visit's start (visit_start_ns[v], UNIX), extra bytes first_visit (1-based).
    void WriteLas(const std::filesystem::path& file,
                  const std::vector<int64_t>& visit_start_ns) const;

    struct Voxel {
        Eigen::Vector3f xyz;
        uint8_t cls = 0;
        uint16_t first = 0, last = 0;
        int32_t element = -1;
    };
    // The voxels in key order (deterministic).
    std::vector<Voxel> Voxels() const;

private:
    struct Entry;
    using Map = std::unordered_map<uint64_t, Entry>;
    uint64_t Key(const Eigen::Vector3f& p) const;
    size_t DropSeenAgain(size_t v);
    size_t DropInBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, size_t before);

    double voxel_, supersede_m_;
    struct Entry {
        Voxel voxel;
    };
    Map voxels_;
};

// Folds every visit in and writes OUT/building_map.ply and OUT/building_map.json (the figures
// per visit, each with the digest of what its fold depended on); returns the latter's value.
// `made_from`: per visit, a digest of what its findings were made from (`bimslam map` gives its
// changes step's stamp digest). The visits the map on disk holds already, folded from the same
// inputs (equal digests), are not folded again: adding a visit folds that visit alone, and the
// map equals a fold of them all.
nlohmann::json WriteBuildingMap(const std::filesystem::path& out,
                                const std::vector<VisitFindings>& visits,
                                const nlohmann::json& history,
                                const std::vector<std::string>& made_from);

}  // namespace bimslam::mapping
