// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/ply.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <random>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/pcd.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::io {
namespace {
namespace BIMSLAM_UNITY_ID {
using common::Error;
using common::FileError;

template <typename T>
void Put(std::string& out, T v, bool big_endian = false) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big_endian) std::reverse(b, b + sizeof(T));
    out.append(b, sizeof(T));
}

common::TriangleMesh SmallMesh() {
    common::TriangleMesh m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0.1f}, {0.5f, 0.5f, 2}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
    return m;
}

TEST(Ply, CloudRoundTripIsBitExact) {
    test::TempDir dir;
    const auto cloud = test::MakeRoomScan(32, 1024, 5);
    for (PlyEncoding enc : {PlyEncoding::kBinaryLittleEndian, PlyEncoding::kAscii}) {
        WritePly(dir / "c.ply", ToPly(cloud), enc);
        const PlyData data = ReadPly(dir / "c.ply");
        ASSERT_EQ(data.vertex_properties.size(), 3u);
        EXPECT_EQ(data.vertex_properties[1].type, PlyType::kUint16);
        EXPECT_TRUE(data.triangles.empty());
        const auto back = PointCloudFromPly(data);
        EXPECT_EQ(back.xyz, cloud.xyz);
        EXPECT_EQ(back.intensity, cloud.intensity);
        EXPECT_EQ(back.ring, cloud.ring);
        // t is float32 seconds as in PCD (see Pcd.TimeOffsetRoundTrip...): the same values.
        EXPECT_EQ(back.time_offset_ns,
                  ParsePcd("p", SerializePcd(cloud, PcdEncoding::kBinary)).time_offset_ns);
        EXPECT_EQ(SerializePly(data, enc), ReadFileToString(dir / "c.ply"));
    }
}

TEST(Ply, MeshRoundTripAndExactAsciiOutput) {
    const auto mesh = SmallMesh();
    for (PlyEncoding enc : {PlyEncoding::kBinaryLittleEndian, PlyEncoding::kAscii}) {
        const auto back = MeshFromPly(ParsePly("m.ply", SerializePly(ToPly(mesh), enc)));
        EXPECT_EQ(back.vertices, mesh.vertices);
        EXPECT_EQ(back.triangles, mesh.triangles);
    }
    common::TriangleMesh tri;
    tri.vertices = {{0, 0, 0}, {1.5f, 0, 0}, {0, -2, 0.1f}};
    tri.triangles = {{0, 1, 2}};
    EXPECT_EQ(SerializePly(ToPly(tri), PlyEncoding::kAscii),
              "ply\nformat ascii 1.0\ncomment bimslam\nelement vertex 3\nproperty float x\n"
              "property float y\nproperty float z\nelement face 1\n"
              "property list uchar int vertex_indices\nend_header\n0 0 0\n1.5 0 0\n0 -2 0.1\n"
              "3 0 1 2\n");
}

TEST(Ply, EveryScalarTypeRoundTripsExactly) {
    using L = std::numeric_limits<double>;
    using F = std::numeric_limits<float>;
    PlyData d;
    d.vertices.assign(4, Eigen::Vector3f(1, 2, 3));
    d.vertex_properties = {
        {"a", PlyType::kInt8, {-128, 127, 0, -1}},
        {"b", PlyType::kUint8, {0, 255, 1, 128}},
        {"c", PlyType::kInt16, {-32768, 32767, 0, -2}},
        {"d", PlyType::kUint16, {0, 65535, 1, 40000}},
        {"e", PlyType::kInt32, {-2147483648.0, 2147483647.0, 0, -3}},
        {"f", PlyType::kUint32, {0, 4294967295.0, 1, 3000000000.0}},
        {"g", PlyType::kFloat32, {F::lowest(), F::max(), F::denorm_min(), 0.1f}},
        {"h", PlyType::kFloat64, {L::lowest(), L::max(), L::denorm_min(), 0.1}},
        {"i", PlyType::kFloat64, {-0.0, 1e-300, 123456789.123456789, -2.5}},
    };
    for (PlyEncoding enc : {PlyEncoding::kBinaryLittleEndian, PlyEncoding::kAscii}) {
        const PlyData back = ParsePly("t.ply", SerializePly(d, enc));
        ASSERT_EQ(back.vertex_properties.size(), d.vertex_properties.size());
        for (size_t k = 0; k < d.vertex_properties.size(); ++k) {
            EXPECT_EQ(back.vertex_properties[k].name, d.vertex_properties[k].name);
            EXPECT_EQ(back.vertex_properties[k].type, d.vertex_properties[k].type);
            EXPECT_EQ(back.vertex_properties[k].values, d.vertex_properties[k].values) << k;
        }
        EXPECT_TRUE(std::signbit(back.Find("i")->values[0]));
        EXPECT_EQ(back.Find("zz"), nullptr);
    }
}

TEST(Ply, ReadsBigEndianListsAndSkipsOtherElements) {
    std::string f =
        "ply\r\nformat binary_big_endian 1.0\r\ncomment from elsewhere\r\n"
        "element vertex 4\r\nproperty double x\r\nproperty double y\r\nproperty double z\r\n"
        "property list uchar int adjacency\r\nproperty uint8 red\r\n"
        "element edge 1\r\nproperty int vertex1\r\nproperty int vertex2\r\n"
        "element face 1\r\nproperty uchar flags\r\nproperty list ushort uint vertex_indices\r\n"
        "property list uchar float texcoord\r\nend_header\r\n";
    for (int i = 0; i < 4; ++i) {
        for (double v : {0.5 * i, -1.0 * i, 2.0}) Put(f, v, true);
        Put(f, uint8_t{2}, true);
        Put(f, int32_t{i}, true);
        Put(f, int32_t{-i}, true);
        Put(f, static_cast<uint8_t>(10 * i), true);
    }
    Put(f, int32_t{0}, true);
    Put(f, int32_t{1}, true);
    Put(f, uint8_t{7}, true);
    Put(f, uint16_t{4}, true);
    for (uint32_t v : {3u, 2u, 1u, 0u}) Put(f, v, true);
    Put(f, uint8_t{2}, true);
    Put(f, 0.25f, true);
    Put(f, 0.75f, true);
    const PlyData d = ParsePly("be.ply", f);
    ASSERT_EQ(d.vertices.size(), 4u);
    EXPECT_EQ(d.vertices[3], Eigen::Vector3f(1.5f, -3.0f, 2.0f));
    ASSERT_EQ(d.vertex_properties.size(), 1u);
    EXPECT_EQ(d.vertex_properties[0].name, "red");
    EXPECT_EQ(d.vertex_properties[0].type, PlyType::kUint8);
    EXPECT_EQ(d.vertex_properties[0].values, (std::vector<double>{0, 10, 20, 30}));
    // The quad is fan-triangulated.
    EXPECT_EQ(d.triangles, (std::vector<std::array<uint32_t, 3>>{{3, 2, 1}, {3, 1, 0}}));
}

TEST(Ply, ReadsAsciiVariants) {
    // Items sharing and spanning lines, aliases, obj_info, a pentagon, vertex_index.
    const PlyData d = ParsePly("v.ply",
                               "ply\nformat ascii 1.0\nobj_info x\nelement vertex 5\n"
                               "property float32 x\nproperty float32 y\nproperty float32 z\n"
                               "property int8 k\nelement face 1\n"
                               "property list uint8 int32 vertex_index\nproperty uchar red\n"
                               "element material 1\nproperty list uchar float c\nend_header\n"
                               "0 0 0 -1 1 0 0 -2\n2 1 0 -3\n  1 2\n0 -4 0 1 +0.5 -5\n"
                               "5 0 1 2 3 4 255\n3 0.1 0.2 0.3\n\n");
    ASSERT_EQ(d.vertices.size(), 5u);
    EXPECT_EQ(d.vertices[4], Eigen::Vector3f(0, 1, 0.5f));
    EXPECT_EQ(d.Find("k")->values, (std::vector<double>{-1, -2, -3, -4, -5}));
    EXPECT_EQ(d.triangles, (std::vector<std::array<uint32_t, 3>>{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}}));
    // PCL's point cloud PLY: an empty face element without properties and a camera element.
    const PlyData pcl = ParsePly("p.ply",
                                 "ply\nformat ascii 1.0\ncomment PCL generated\nelement vertex 1\n"
                                 "property float x\nproperty float y\nproperty float z\n"
                                 "element face 0\nelement camera 1\nproperty float view_px\n"
                                 "property int viewportx\nend_header\n1 2 3\n0 640\n");
    EXPECT_EQ(pcl.vertices.at(0), Eigen::Vector3f(1, 2, 3));
}

TEST(Ply, RejectsBadHeadersNamingTheLine) {
    const std::string v = "ply\nformat ascii 1.0\nelement vertex 1\n";
    const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
    EXPECT_FILE_ERROR(ParsePly("e.ply", ""), "e.ply", 1);
    EXPECT_FILE_ERROR(ParsePly("g.ply", "PK\x03\x04garbage"), "g.ply", 1);
    EXPECT_FILE_ERROR(ParsePly("h.ply", "ply\n"), "h.ply", 1);
    EXPECT_FILE_ERROR(ParsePly("h.ply", "ply\nformat ascii 2.0\n"), "h.ply", 2);
    EXPECT_FILE_ERROR(ParsePly("h.ply", "ply\nformat utf8 1.0\n"), "h.ply", 2);
    EXPECT_FILE_ERROR(ParsePly("h.ply", "ply\nformat ascii 1.0\nproperty float x\n"), "h.ply", 3);
    EXPECT_FILE_ERROR(ParsePly("h.ply", v + "property real x\n"), "h.ply", 4);
    EXPECT_FILE_ERROR(ParsePly("h.ply", v + "property list float int x\n"), "h.ply", 4);
    EXPECT_FILE_ERROR(ParsePly("h.ply", v + xyz + "property float x\n"), "h.ply", 7);
    EXPECT_FILE_ERROR(ParsePly("h.ply", v + "element vertex 2\n"), "h.ply", 4);
    EXPECT_FILE_ERROR(ParsePly("h.ply", "ply\nformat ascii 1.0\nelement vertex -1\n"), "h.ply", 3);
    EXPECT_FILE_ERROR(ParsePly("h.ply", v + xyz + "frobnicate\n"), "h.ply", 7);
    EXPECT_FILE_ERROR(ParsePly("h.ply", v + xyz), "h.ply", 6);
    EXPECT_FILE_ERROR(ParsePly("h.ply", "ply\nelement vertex 0\n" + xyz + "end_header\n"), "h.ply",
                      6);
    EXPECT_FILE_ERROR(
        ParsePly("h.ply", v + "property float x\nproperty float y\nend_header\n0 0\n"), "h.ply", 6);
    EXPECT_FILE_ERROR(ParsePly("h.ply", "ply\nformat ascii 1.0\nelement face 0\nend_header\n"),
                      "h.ply", 4);
    EXPECT_FILE_ERROR(ParsePly("h.ply", v + xyz +
                                            "element face 1\nproperty uchar n\nend_header\n"
                                            "0 0 0\n3\n"),
                      "h.ply", 9);
    EXPECT_FILE_ERROR(ReadPly("/nonexistent/m.ply"), "/nonexistent/m.ply", 0);
}

TEST(Ply, RejectsBadAsciiBodiesNamingTheLine) {
    // Lines 1-11 are the header, vertices from line 12, faces after them.
    const std::string mesh = SerializePly(ToPly(SmallMesh()), PlyEncoding::kAscii);
    const std::string cloud = SerializePly(ToPly(test::MakeRoomScan(2, 3, 1)), PlyEncoding::kAscii);
    const size_t v1 = cloud.find("end_header\n") + 11;
    auto with_line = [&](const std::string& line) {
        return cloud.substr(0, v1) + line + "\n" + cloud.substr(cloud.find('\n', v1) + 1);
    };
    EXPECT_EQ(PointCloudFromPly(ParsePly("a.ply", with_line("1 2 3 4 5 0"))).ring.at(0), 5);
    EXPECT_FILE_ERROR(ParsePly("a.ply", with_line("1 2 nan 4 5 0")), "a.ply", 12);
    EXPECT_FILE_ERROR(ParsePly("a.ply", with_line("1 2 3 inf 5 0")), "a.ply", 12);
    EXPECT_FILE_ERROR(ParsePly("a.ply", with_line("1 2 1e39 4 5 0")), "a.ply", 12);
    EXPECT_FILE_ERROR(ParsePly("a.ply", with_line("1 2 3 4 65536 0")), "a.ply", 12);
    EXPECT_FILE_ERROR(ParsePly("a.ply", with_line("1 2 3 4 5.5 0")), "a.ply", 12);
    EXPECT_FILE_ERROR(ParsePly("a.ply", with_line("1 2 3 4 5 0x1")), "a.ply", 12);
    // Items may span lines, so a short last line or a cut file fails where the data ends.
    const size_t last = cloud.rfind('\n', cloud.size() - 2) + 1;
    EXPECT_FILE_ERROR(ParsePly("a.ply", cloud.substr(0, last) + "1 2 3 4 5\n"), "a.ply", 17);
    EXPECT_FILE_ERROR(ParsePly("a.ply", cloud.substr(0, last + 8)), "a.ply", 17);
    EXPECT_FILE_ERROR(ParsePly("a.ply", cloud + "1\n"), "a.ply", 18);
    const size_t f1 = mesh.rfind("3 3 0 4\n");
    ASSERT_NE(f1, std::string::npos);
    EXPECT_FILE_ERROR(ParsePly("m.ply", mesh.substr(0, f1) + "3 3 0 5\n"), "m.ply", 21);
    EXPECT_FILE_ERROR(ParsePly("m.ply", mesh.substr(0, f1) + "3 3 0 -1\n"), "m.ply", 21);
    EXPECT_FILE_ERROR(ParsePly("m.ply", mesh.substr(0, f1) + "2 3 0\n"), "m.ply", 21);
    EXPECT_FILE_ERROR(ParsePly("m.ply", mesh.substr(0, f1) + "256 3 0\n"), "m.ply", 21);
    // A lying count is caught at its header line before anything is allocated.
    std::string lie = cloud;
    lie.replace(lie.find("vertex 6"), 8, "vertex 4000000000");
    EXPECT_FILE_ERROR(ParsePly("a.ply", lie), "a.ply", 4);
}

TEST(Ply, RejectsBadBinaryBodiesWithoutLine) {
    const std::string mesh = SerializePly(ToPly(SmallMesh()), PlyEncoding::kBinaryLittleEndian);
    const std::string cloud =
        SerializePly(ToPly(test::MakeRoomScan(2, 3, 1)), PlyEncoding::kBinaryLittleEndian);
    // Fixed-size items are checked against the file size at their element's header line;
    // variable ones (faces) fail where the data ends.
    EXPECT_FILE_ERROR(ParsePly("b.ply", cloud.substr(0, cloud.size() - 1)), "b.ply", 4);
    EXPECT_FILE_ERROR(ParsePly("b.ply", mesh.substr(0, mesh.size() - 2)), "b.ply", 0);
    const size_t body = cloud.find("end_header\n") + 11;
    std::string inf = cloud;
    const float big = std::numeric_limits<float>::infinity();
    std::memcpy(inf.data() + body + 22 * 3 + 12, &big, 4);  // intensity of vertex 3
    EXPECT_FILE_ERROR(ParsePly("b.ply", inf), "b.ply", 0);
    std::string bad_index = mesh;
    const int32_t five = 5;
    std::memcpy(bad_index.data() + bad_index.size() - 4, &five, 4);
    EXPECT_FILE_ERROR(ParsePly("b.ply", bad_index), "b.ply", 0);
    std::string two_corners = mesh;
    two_corners[two_corners.size() - 13] = 2;
    EXPECT_FILE_ERROR(ParsePly("b.ply", two_corners), "b.ply", 0);
    std::string lie = cloud;
    lie.replace(lie.find("vertex 6"), 8, "vertex 4000000000");
    EXPECT_FILE_ERROR(ParsePly("b.ply", lie), "b.ply", 4);
    // Trailing bytes after binary data are ignored, as other readers do.
    EXPECT_EQ(ParsePly("b.ply", mesh + "\n\n").triangles.size(), 6u);
}

TEST(Ply, WriterAndConversionsRejectWhatTheFormatCannotHold) {
    test::TempDir dir;
    const std::string path = (dir / "w.ply").string();
    PlyData d = ToPly(test::MakeRoomScan(2, 3, 1));
    d.vertex_properties[1].values[2] = 70000;  // ring is uint16
    EXPECT_FILE_ERROR(WritePly(path, d), path, 0);
    EXPECT_THROW(PointCloudFromPly(d), Error);
    d.vertex_properties[1].values[2] = 1.5;
    EXPECT_FILE_ERROR(WritePly(path, d), path, 0);
    d = ToPly(test::MakeRoomScan(2, 3, 1));
    d.vertex_properties[0].values[0] = std::nan("");
    EXPECT_FILE_ERROR(WritePly(path, d), path, 0);
    d = ToPly(test::MakeRoomScan(2, 3, 1));
    d.vertex_properties[2].values.pop_back();
    EXPECT_FILE_ERROR(WritePly(path, d), path, 0);
    EXPECT_THROW(PointCloudFromPly(d), Error);
    for (const char* name : {"x", "ring", "", "a b"}) {
        d = ToPly(test::MakeRoomScan(2, 3, 1));
        d.vertex_properties[0].name = name;
        EXPECT_FILE_ERROR(WritePly(path, d), path, 0);
    }
    auto mesh = ToPly(SmallMesh());
    mesh.triangles[2][1] = 5;
    EXPECT_FILE_ERROR(WritePly(path, mesh), path, 0);
    EXPECT_THROW(MeshFromPly(mesh), Error);
    EXPECT_FALSE(std::filesystem::exists(path));
    // t of a negative or integer type: an integer t is nanoseconds.
    d = ToPly(test::MakeRoomScan(2, 3, 1));
    d.vertex_properties[2].values[1] = -0.001;
    EXPECT_THROW(PointCloudFromPly(d), Error);
    d.vertex_properties[2].type = PlyType::kUint32;
    d.vertex_properties[2].values.assign(d.vertices.size(), 12345);
    EXPECT_EQ(PointCloudFromPly(ParsePly("n.ply", SerializePly(d, PlyEncoding::kAscii)))
                  .time_offset_ns.at(5),
              12345u);
    auto cloud = test::MakeRoomScan(2, 3, 1);
    cloud.intensity.pop_back();
    EXPECT_THROW(ToPly(cloud), Error);
}

// Random byte edits of valid files must only ever produce data or a FileError (run under ASan
// and UBSan too).
constexpr char kInterestingPly[] = "0123456789 \n-.e+n\x00\xff\x7f\x80\x03";

TEST(Ply, MutatedFilesOnlyEverThrowFileError) {
    PlyData both = ToPly(test::MakeRoomScan(2, 3, 2));
    both.triangles = {{0, 1, 2}, {3, 4, 5}, {5, 0, 1}};
    std::vector<std::string> seeds = {SerializePly(both, PlyEncoding::kBinaryLittleEndian),
                                      SerializePly(both, PlyEncoding::kAscii)};
    std::string be = seeds[0];  // the same header read as big-endian: other values, same code
    be.replace(be.find("binary_little_endian"), 20, "binary_big_endian");
    seeds.push_back(be);
    std::vector<test::FuzzSeed> fuzz_seeds;
    for (const std::string& seed : seeds)
        fuzz_seeds.push_back({seed, seed.find("end_header") + 11});
    const auto [parsed, rejected] = test::FuzzReader(
        "fuzz.ply", fuzz_seeds, 3000, 77, {kInterestingPly, sizeof(kInterestingPly) - 1},
        [](const std::string& b) { ParsePly("fuzz.ply", b); });
    EXPECT_GT(rejected, 1000u);
    EXPECT_GT(parsed, 100u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::io
