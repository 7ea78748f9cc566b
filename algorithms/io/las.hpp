// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// ASPRS LAS 1.4 point clouds (LAS Specification 1.4 R15, ASPRS 2019), as the tools of surveyors
// and BIM users load them (CloudCompare, Recap, Navisworks, Cyclone, PDAL, LAStools): point data
// record format 6 (x y z, intensity, returns, classification, user data, point source id, GPS
// time; 30 bytes) with fields of our own after it, declared in the Extra Bytes VLR (user id
// "LASF_Spec", record id 4; R15 section 2.6 / Table 24). Uncompressed; no CRS VLR (the model's
// own coordinates, which have none). Written by hand: no Debian 12 package writes LAS 1.4 (LASzip,
// PDAL and libLAS are not in Debian 12; algorithms/io/README.md).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace bimslam::io {

// The data types of an extra-bytes field (R15 Table 25: 1 unsigned char ... 10 double).
enum class LasType : uint8_t {
    kUint8 = 1,
    kInt8 = 2,
    kUint16 = 3,
    kInt16 = 4,
    kUint32 = 5,
    kInt32 = 6,
    kUint64 = 7,
    kInt64 = 8,
    kFloat32 = 9,
    kFloat64 = 10
};
size_t LasTypeSize(LasType type);

// One extra-bytes field: one value per point, held as double (exact for every type but 64-bit
// integers beyond 2^53, which the writer refuses).
struct LasExtraField {
    std::string name;  // at most 31 characters (the field holds 32 with a terminating NUL)
    LasType type = LasType::kFloat32;
    std::string description;        // at most 31 characters
    std::optional<double> no_data;  // written with the "no_data" option bit
    std::vector<double> values;
};

// ASPRS classes (R15 Table 17, point formats 6-10) that bimslam writes; 64-255 are user-defined.
inline constexpr uint8_t kLasClassUnclassified = 1;
inline constexpr uint8_t kLasClassBuilding = 6;
inline constexpr uint8_t kLasClassFirstUser = 64;

// A point cloud as format 6 carries it. Every per-point vector is empty (all zero) or one per
// point; one return per point (return 1 of 1).
struct LasData {
    std::vector<Eigen::Vector3d> xyz;  // metres
    std::vector<uint16_t> intensity;
    std::vector<uint8_t> classification;
    std::vector<uint8_t> user_data;
    std::vector<uint16_t> point_source_id;
    std::vector<double> gps_time;  // seconds, of the kind `adjusted_standard_gps_time` says
    std::vector<LasExtraField> extra;

    // Header. Global encoding bit 0: set, GPS time is adjusted standard GPS time (GPS seconds
    // minus 1e9); clear, GPS week time (or, as bimslam writes it without a known clock, the
    // sensor's own clock: algorithms/io/README.md).
    bool adjusted_standard_gps_time = true;
    uint16_t file_source_id = 0;
    std::string system_identifier = "bimslam";
    std::string generating_software = "bimslam";
    uint16_t creation_day_of_year = 0;  // 1-366; 0 with year 0: unknown
    uint16_t creation_year = 0;
    // Coordinates are stored as int32 counts of `scale` from `offset`. The writer picks the
    // offset (the bounding box's minimum, rounded down to a whole metre) unless told.
    double scale = 1e-4;
    std::optional<Eigen::Vector3d> offset;

    size_t size() const { return xyz.size(); }
    const LasExtraField* Find(std::string_view name) const;
};

// The whole file as bytes. Throws common::Error (kInvalidArgument) on a vector whose length is
// neither 0 nor the point count, a non-finite coordinate or GPS time, a coordinate that does not
// fit in int32 counts of the scale, an extra-bytes value its type cannot hold (NaN is allowed in
// float fields), a name or description too long, or duplicate field names.
std::string SerializeLas(const LasData& data);

// SerializeLas, written atomically (io::WriteFileAtomic). Throws common::FileError naming the file.
void WriteLas(const std::filesystem::path& path, const LasData& data);

// Reads what WriteLas writes, and any uncompressed LAS 1.4 file of point format 6 (other VLRs
// skipped, extra bytes of types 1-10 read; undocumented ones skipped). Coordinates come back as
// stored (quantised to the scale); `offset` is set to the file's. Throws common::FileError naming
// the file and what is wrong on a bad signature, version, format, record length, truncation or
// a malformed Extra Bytes VLR.
LasData ReadLas(const std::filesystem::path& path);
LasData ParseLas(const std::string& name, std::string_view bytes);

// Adjusted standard GPS time (R15, Global Encoding bit 0: GPS seconds since 1980-01-06 minus 1e9)
// of a UNIX time, with the leap seconds of IERS Bulletin C up to 2017-01-01 (GPS - UTC = 18 s
// since; none announced since). Times before 1980-01-06 are not GPS times: the caller's problem.
double UnixNsToAdjustedGpsSeconds(int64_t unix_ns);

// Sets the header's creation day of year and year to the UTC day of `unix_ns`.
void SetLasCreationDate(LasData& data, int64_t unix_ns);

}  // namespace bimslam::io
