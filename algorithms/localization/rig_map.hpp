// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The rig's map package (issue 35, item 1): what relocalising in the building's model needs on
// board, and nothing more: the BIM reference's keyframes (poses in the model's frame, storey,
// Scan Context descriptor), its surfel pyramid as anchoring registers to it, the storeys, and
// the model it came from (file name and SHA-256). One file, versioned and checksummed; its layout
// is in algorithms/localization/README.md, "The rig map format". `bimslam rig-map` writes it from
// a model's reference session; the rig reads it.
//
// Reading is bounded: the file's size is checked against a limit before anything is read, every
// count against the bytes that hold it before anything is allocated, and the CRC-32 of every byte
// before anything is parsed. A damaged, truncated, foreign or newer file is refused, naming it.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/io/session.hpp"
#include "algorithms/registration/registration.hpp"
#include "algorithms/registration/surfel_map.hpp"
#include "algorithms/scancontext/config.hpp"
#include "algorithms/scancontext/descriptor.hpp"

namespace bimslam::localization {

inline constexpr uint32_t kRigMapVersion = 1;

struct RigMapStorey {
    std::string name;
    std::string global_id;
    double elevation_m = 0;  // IfcBuildingStorey.Elevation, in the model's frame
};

// An IfcSpace as the rig looks it up: the footprint of its horizontal faces (triangles in the
// model's x y, three points each) between its lowest and highest z.
struct RigMapSpace {
    std::string name;  // its LongName, else its Name
    std::string global_id;
    int32_t storey = -1;
    float z_min = 0, z_max = 0;
    std::vector<Eigen::Vector2f> triangles;
};

struct RigMap {
    // The model: its file's name (not its path: the package travels) and SHA-256 (hex), which a
    // rig's configuration can name to refuse a package of another model.
    std::string model_file;
    std::string model_sha256;
    std::string frame = "bim";           // the frame of the keyframes' poses and the surfels
    std::string created;                 // ISO 8601 UTC
    std::string reference;               // the reference session it was made from, as given
    io::SessionManifest::Sensor sensor;  // the reference's simulated sensor
    io::SessionManifest::Descriptor descriptor;  // how the descriptors were made
    std::vector<RigMapStorey> storeys;           // by elevation

    // Per reference keyframe: T_bim_lidar, its storey (index into storeys; -1 when none lies
    // below it) and its descriptor (descriptor.rings x descriptor.sectors).
    std::vector<Eigen::Isometry3d> keyframes;
    std::vector<int32_t> keyframe_storey;
    std::vector<scancontext::Descriptor> descriptors;

    // The surfel pyramid's levels, built, in the order of the anchoring's RegistrationConfig.
    std::vector<registration::SurfelMap> levels;

    // The model's spaces (an optional section, SPAC: a package without it reads as none).
    std::vector<RigMapSpace> spaces;

    registration::SurfelPyramid Pyramid() const { return registration::SurfelPyramid(levels); }
    // The Scan Context configuration `descriptor` describes (a query keyframe's descriptor must be
    // made with it).
    scancontext::ScanContextConfig DescriptorConfig() const;
};

// The space (index into map.spaces) holding point p: within its heights and over one of its
// footprint's triangles; -1 in none.
int SpaceAt(const RigMap& map, const Eigen::Vector3d& p);

// The storey a point at height z is on: the highest storey whose elevation is at most z (the
// sensor rides above its floor); -1 below every storey. `storeys` by elevation.
int32_t StoreyAt(const std::vector<RigMapStorey>& storeys, double z);

// The whole file as bytes. Throws common::Error (kInvalidArgument) on counts that differ (a
// descriptor per keyframe, its shape the manifest's), a non-finite pose or a storey index out of
// range.
std::string SerializeRigMap(const RigMap& map);
// SerializeRigMap, written atomically. Throws common::FileError naming the file.
void WriteRigMap(const std::filesystem::path& path, const RigMap& map);

// At most this many bytes are read (a five-storey building's package is about 40 MB).
inline constexpr size_t kRigMapMaxBytes = size_t(512) << 20;

// Reads a package. Throws common::FileError naming the file, the byte and what is wrong: not a
// rig map, another version, larger than max_bytes, truncated, a CRC-32 that does not match,
// a section missing or of the wrong size, counts that disagree, a non-finite or non-rigid pose.
RigMap ReadRigMap(const std::filesystem::path& path, size_t max_bytes = kRigMapMaxBytes);
RigMap ParseRigMap(const std::string& name, std::string_view bytes);

}  // namespace bimslam::localization
