// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// PLY files (http://paulbourke.net/dataformats/ply/): point clouds and triangle meshes, ASCII and
// binary little-endian, with extra per-vertex properties (e.g. the BIM element index of a vertex).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/common/point_cloud.hpp"
#include "algorithms/common/triangle_mesh.hpp"

namespace bimslam::io {

enum class PlyEncoding { kAscii, kBinaryLittleEndian };

// The PLY scalar types: char uchar short ushort int uint float double (and their int8... aliases).
enum class PlyType : uint8_t {
    kInt8,
    kUint8,
    kInt16,
    kUint16,
    kInt32,
    kUint32,
    kFloat32,
    kFloat64
};

// One extra per-vertex property. Values are held as double, which represents every value of every
// PLY scalar type exactly, so a read-write round trip is bit-exact for the declared type.
struct PlyProperty {
    std::string name;
    PlyType type = PlyType::kFloat32;
    std::vector<double> values;  // one per vertex
};

// What a PLY file holds, as this project uses it.
struct PlyData {
    // Vertex positions (x y z); stored as float32 when written.
    std::vector<Eigen::Vector3f> vertices;
    // Every other vertex property, in file order (intensity, ring, element, nx, red, ...).
    std::vector<PlyProperty> vertex_properties;
    // Faces as triangles; polygons with more corners are fan-triangulated on read.
    std::vector<std::array<uint32_t, 3>> triangles;

    // The property named `name`, or nullptr.
    const PlyProperty* Find(std::string_view name) const;
};

// Writes "ply", the format line, "comment bimslam", element vertex with float x y z and the extra
// properties (type names char uchar short ushort int uint float double, as the spec lists them),
// and, when there are triangles, element face with "property list uchar int vertex_indices".
// Rejects (common::FileError naming the file) property values that the declared type cannot hold
// (non-integral or out of range integers, non-finite floats), property lengths that differ from
// the vertex count, duplicate or malformed names and out-of-range triangle indices. Atomic.
void WritePly(const std::filesystem::path& path, const PlyData& data,
              PlyEncoding encoding = PlyEncoding::kBinaryLittleEndian);

// Reads ascii, binary_little_endian and binary_big_endian. Needs a vertex element with x, y, z
// (any type, stored as float); other scalar vertex properties become vertex_properties, vertex
// list properties are skipped. A face element with items needs an integer list "vertex_indices"
// (or "vertex_index"); faces with fewer than 3 corners are an error (PCL writes "element face 0"
// without properties for clouds, which is fine). Other elements (edges, materials, PCL's camera)
// and other face properties are skipped. ASCII items may span or share lines (the spec only says
// whitespace-separated); data after the last element is an error, trailing bytes after binary
// data are ignored. A header whose element counts need more bytes than the file holds is an
// error (at the element's line) before anything is allocated. Throws common::FileError naming the
// file (and the line for header and ASCII errors) on any malformed, truncated or non-finite input,
// or on a face index out of range.
PlyData ReadPly(const std::filesystem::path& path);

PlyData ParsePly(const std::string& name, std::string_view bytes);
std::string SerializePly(const PlyData& data, PlyEncoding encoding);

// The serializer throws common::Error (kInvalidArgument) where WritePly throws FileError.
// Conversions: a point cloud's intensity/ring/t channels become properties "intensity" (float32),
// "ring" (uint16) and "t" (float32 seconds, PcdNsToSeconds of io/pcd.hpp), and back: "t" of a
// float type is seconds, of an integer type nanoseconds, as for PCD. PointCloudFromPly and
// MeshFromPly throw common::Error (kOutOfRange / kInvalidArgument) on values the cloud or mesh
// cannot hold (ring 70000, t < 0, an index out of range, lengths that differ).
PlyData ToPly(const common::PointCloud& cloud);
common::PointCloud PointCloudFromPly(const PlyData& data);
PlyData ToPly(const common::TriangleMesh& mesh);
common::TriangleMesh MeshFromPly(const PlyData& data);

}  // namespace bimslam::io
