// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// BIM -> reference session (paper, Step 1): per storey an occupancy grid, a coverage walk through
// every room, the walks joined by the stairs between the storeys (reference_walk.hpp), and along it
// keyframes whose scans are ray-cast against the model, written as the ground-truth session of
// specs/session-data.md (source "bim", world frame "bim").
//
// The paper drove a simulated robot through Gazebo in real time; here nothing moves: the walk is
// planned on the grid, the keyframe poses are taken from it every `keyframe_gap_m`, and each
// keyframe's scan is cast directly from its pose (a static scan, as a robot standing there would
// see it). What is cast against is the paper's semantic filter: the permanent structure, unless
// `all_elements` is set, because doors, furniture and the like are not where the model says.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "algorithms/io/session.hpp"
#include "algorithms/simulation/lidar_model.hpp"
#include "algorithms/simulation/lidar_simulator.hpp"
#include "host_tools/bim/bim_model.hpp"
#include "host_tools/bim/coverage_path.hpp"
#include "host_tools/bim/occupancy_grid.hpp"

namespace bimslam::bim {

struct ReferenceSessionOptions {
    std::vector<std::string> storeys;  // by name; empty: every storey
    simulation::LidarModel lidar = simulation::LidarModel::DefaultOs1_32();
    std::string sensor_model = "OS-1-32";  // session.json sensor.model
    std::string metadata_file;             // session.json sensor.metadata_file, when one was given
    double keyframe_gap_m = 1.0;           // a keyframe every this many metres along the walk
    bool all_elements = false;             // cast against everything, not only the structure
    // The reference is the model itself: no noise and no dropouts by default, ranges quantised to
    // the 1 mm of an Ouster range field. Realistic noise is available for experiments.
    simulation::NoiseModel noise = simulation::NoiseModel::Noiseless();
    uint64_t seed = 1;
    GridConfig grid;
    PathConfig path;
    bool overwrite = false;
    // Where to also write each storey's grid (PGM + YAML + PNG), path PNG and walk TUM; none when
    // empty.
    std::filesystem::path plan_dir;
    // Called after each keyframe with (keyframes done, keyframes planned).
    std::function<void(size_t, size_t)> progress;

    void Validate() const;  // throws common::Error naming the field and value
};

struct StoreyReport {
    std::string name;
    int regions = 1;  // enclosed regions walked (reference_walk.hpp)
    int rooms = 0;
    int viewpoints = 0;
    int unreachable_viewpoints = 0;
    double free_area_m2 = 0;
    double walk_m = 0;
    double walk_s = 0;     // the walk's duration at the path's walking speed
    size_t keyframes = 0;  // on its floor (not on a flight)
};

struct ReferenceSessionReport {
    std::vector<StoreyReport> storeys;  // by elevation
    size_t keyframes = 0;
    size_t flights_walked = 0;       // flights joining the storeys' walks
    size_t flight_keyframes = 0;     // on the flights and the ways to and from them
    std::vector<std::string> notes;  // storeys not joined by a flight, and why
    size_t points = 0;               // in all keyframe clouds
    size_t rays = 0;                 // cast
    double walk_s = 0;               // real-time duration of the walk, flights included
    double plan_s = 0;               // grids and paths
    double simulate_s = 0;           // ray casting, descriptors
    double write_s = 0;              // session files
};

// The files of a storey's plan in `dir`, named after the storey ("Ground Floor" ->
// "ground_floor"): NAME.pgm/.yaml/.png (the grid), NAME_path.png, NAME_path.tum.
std::string StoreyFileStem(const std::string& storey_name);
void WriteStoreyPlan(const std::filesystem::path& dir, const OccupancyGrid& grid,
                     const CoveragePath& path);

// Writes the reference session of `model` (its `file` and `sha256` go to session.json) to `dir`.
// Throws common::Error for an unknown storey (FindStorey), a storey without enclosed
// free space, or options out of range; common::FileError when the session cannot be written.
ReferenceSessionReport WriteReferenceSession(const BimModel& model, const std::string& model_sha256,
                                             const std::filesystem::path& dir,
                                             const ReferenceSessionOptions& options);

}  // namespace bimslam::bim
