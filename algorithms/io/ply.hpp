// PLY files (http://paulbourke.net/dataformats/ply/): point clouds and triangle meshes, ASCII and
// binary little-endian, with extra per-vertex properties (e.g. the BIM element index of a vertex).
#pragma once

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
enum class PlyType : uint8_t { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

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

void WritePly(const std::filesystem::path& path, const PlyData& data,
              PlyEncoding encoding = PlyEncoding::kBinaryLittleEndian);

// Reads ascii, binary_little_endian and binary_big_endian. Needs a vertex element with x, y, z;
// other elements (edges, materials) are skipped. Throws common::FileError naming the file (and the
// line for header and ASCII errors) on any malformed, truncated or non-finite input, or on a face
// index out of range.
PlyData ReadPly(const std::filesystem::path& path);

PlyData ParsePly(const std::string& name, std::string_view bytes);
std::string SerializePly(const PlyData& data, PlyEncoding encoding);

// Conversions: a point cloud's intensity/ring/t channels become properties "intensity",
// "ring" (uint16) and "t" (float32 s), and back.
PlyData ToPly(const common::PointCloud& cloud);
common::PointCloud PointCloudFromPly(const PlyData& data);
PlyData ToPly(const common::TriangleMesh& mesh);
common::TriangleMesh MeshFromPly(const PlyData& data);

}  // namespace bimslam::io
