// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Interoperability of our PCD, PLY and npy files with the tools people open them in: PCL's
// command-line tools (Debian pcl-tools), Open3D and numpy (python3-open3d, Debian's python) and
// CloudCompare (cloudcompare). Each tool reads our files and writes what it read; we read that back
// and compare values. A missing tool skips its test, naming the package.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <fstream>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/npy.hpp"
#include "algorithms/io/pcd.hpp"
#include "algorithms/io/ply.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::io {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;

const char* const kPython = "/usr/bin/python3";  // Debian's python: the pyenv one has no open3d

std::string Quote(const fs::path& p) { return "'" + p.string() + "'"; }

// Runs a shell command with its output in `log`; returns the exit status.
int RunTool(const std::string& command, const fs::path& log) {
    const int rc = std::system((command + " >" + Quote(log) + " 2>&1").c_str());
    return rc == -1 ? -1 : WEXITSTATUS(rc);
}

#define EXPECT_RUNS(command, dir)                                         \
    do {                                                                  \
        const fs::path log_ = (dir) / "tool.log";                         \
        const int rc_ = RunTool(command, log_);                           \
        ASSERT_EQ(rc_, 0) << (command) << "\n" << ReadFileToString(log_); \
    } while (0)

const common::PointCloud& Scan() {
    static const common::PointCloud cloud = test::MakeRoomScan(32, 1024, 21);
    return cloud;
}

// What we read back from our own files: t quantised to float32 seconds (io/pcd.hpp).
const common::PointCloud& Reference() {
    static const common::PointCloud cloud =
        ParsePcd("reference", SerializePcd(Scan(), PcdEncoding::kBinary));
    return cloud;
}

void ExpectSameCloud(const common::PointCloud& actual, const std::string& what) {
    const common::PointCloud& ref = Reference();
    ASSERT_EQ(actual.size(), ref.size()) << what;
    EXPECT_TRUE(actual.xyz == ref.xyz) << what;
    EXPECT_TRUE(actual.intensity == ref.intensity) << what;
    EXPECT_TRUE(actual.ring == ref.ring) << what;
    EXPECT_TRUE(actual.time_offset_ns == ref.time_offset_ns) << what;
}

// A 40 x 30 vertex grid with a bump, 2 triangles a cell.
common::TriangleMesh GridMesh() {
    common::TriangleMesh m;
    for (int r = 0; r < 30; ++r) {
        for (int c = 0; c < 40; ++c) {
            m.vertices.emplace_back(0.1f * c, 0.13f * r, std::sin(0.2f * c) * std::cos(0.3f * r));
        }
    }
    for (uint32_t r = 0; r + 1 < 30; ++r) {
        for (uint32_t c = 0; c + 1 < 40; ++c) {
            const uint32_t i = r * 40 + c;
            m.triangles.push_back({i, i + 1, i + 41});
            m.triangles.push_back({i, i + 41, i + 40});
        }
    }
    return m;
}

TEST(PclInterop, PclReadsOurPcdAndWritesWhatWeWrite) {
    const fs::path tool = "/usr/bin/pcl_convert_pcd_ascii_binary";
    if (!fs::exists(tool)) GTEST_SKIP() << tool << " is missing: install the package pcl-tools";
    test::TempDir dir;
    WritePcd(dir / "ours_bin.pcd", Scan(), PcdEncoding::kBinary);
    WritePcd(dir / "ours_ascii.pcd", Scan(), PcdEncoding::kAscii);
    for (const char* src : {"ours_bin.pcd", "ours_ascii.pcd"}) {
        // 0 ascii (9 digits: exact for float32), 1 binary, 2 binary_compressed (LZF).
        for (const char* mode : {"0", "1", "2"}) {
            const fs::path out = dir / (std::string("pcl_") + mode + "_" + src);
            EXPECT_RUNS(Quote(tool) + " " + Quote(dir / src) + " " + Quote(out) + " " + mode + " 9",
                        dir.path());
            ExpectSameCloud(ReadPcd(out), std::string("PCL mode ") + mode + " from " + src);
        }
    }
    // PCL's header is ours line for line, and its binary data is ours plus zero padding.
    const std::string ours = ReadFileToString(dir / "ours_ascii.pcd");
    const std::string header = ours.substr(0, ours.find("DATA ascii\n") + 11);
    EXPECT_EQ(ReadFileToString(dir / "pcl_0_ours_bin.pcd").substr(0, header.size()), header);
    const std::string ours_bin = ReadFileToString(dir / "ours_bin.pcd");
    const std::string pcl_bin = ReadFileToString(dir / "pcl_1_ours_ascii.pcd");
    ASSERT_GE(pcl_bin.size(), ours_bin.size());
    EXPECT_EQ(pcl_bin.substr(0, ours_bin.size()), ours_bin);
    EXPECT_EQ(pcl_bin.find_first_not_of('\0', ours_bin.size()), std::string::npos);
}

TEST(PclInterop, PclReadsOurPlyAndWeReadPcls) {
    const fs::path ply2pcd = "/usr/bin/pcl_ply2pcd", pcd2ply = "/usr/bin/pcl_pcd2ply";
    if (!fs::exists(ply2pcd) || !fs::exists(pcd2ply)) {
        GTEST_SKIP() << ply2pcd << " or " << pcd2ply << " is missing: install pcl-tools";
    }
    test::TempDir dir;
    WritePly(dir / "ours_bin.ply", ToPly(Scan()), PlyEncoding::kBinaryLittleEndian);
    WritePly(dir / "ours_ascii.ply", ToPly(Scan()), PlyEncoding::kAscii);
    for (const char* src : {"ours_bin.ply", "ours_ascii.ply"}) {
        const fs::path out = dir / (std::string(src) + ".pcd");
        EXPECT_RUNS(Quote(ply2pcd) + " " + Quote(dir / src) + " " + Quote(out), dir.path());
        ExpectSameCloud(ReadPcd(out), std::string("pcl_ply2pcd of ") + src);
    }
    // PCL's PLY: "element face 0" without properties and a camera element, which we skip.
    WritePcd(dir / "ours.pcd", Scan());
    EXPECT_RUNS(
        Quote(pcd2ply) + " -format 1 " + Quote(dir / "ours.pcd") + " " + Quote(dir / "pcl_bin.ply"),
        dir.path());
    ExpectSameCloud(PointCloudFromPly(ReadPly(dir / "pcl_bin.ply")), "pcl_pcd2ply binary");
    EXPECT_RUNS(Quote(pcd2ply) + " -format 0 " + Quote(dir / "ours.pcd") + " " +
                    Quote(dir / "pcl_ascii.ply"),
                dir.path());
    // PCL prints ASCII PLY floats with 8 significant digits: within one float step, not exact.
    const auto ascii = PointCloudFromPly(ReadPly(dir / "pcl_ascii.ply"));
    ASSERT_EQ(ascii.size(), Reference().size());
    EXPECT_EQ(ascii.ring, Reference().ring);
    EXPECT_EQ(ascii.intensity, Reference().intensity);
    for (size_t i = 0; i < ascii.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            const float a = ascii.xyz[i][k], b = Reference().xyz[i][k];
            ASSERT_LE(std::abs(a - b), 2.0f * std::abs(b) * 0x1p-24f + 1e-30f) << i;
        }
    }
}

// Reads our files with Open3D (legacy and tensor API) and saves what it got as .npy with numpy;
// checks that numpy reads our .npy and writes the same bytes we do.
constexpr const char* kOpen3dScript = R"(
import sys
import numpy as np
import open3d as o3d
d = sys.argv[1]
o3d.utility.set_verbosity_level(o3d.utility.VerbosityLevel.Error)
def save(name, a):
    np.save(f"{d}/{name}.npy", np.ascontiguousarray(a))
for f in ["c_bin.pcd", "c_ascii.pcd", "c_bin.ply", "c_ascii.ply"]:
    save(f + ".legacy", np.asarray(o3d.io.read_point_cloud(f"{d}/{f}").points))
    t = o3d.t.io.read_point_cloud(f"{d}/{f}")
    for key in ["positions", "intensity", "ring", "t"]:
        if key in t.point:
            save(f + "." + key, t.point[key].numpy())
for f in ["m_bin.ply", "m_ascii.ply"]:
    m = o3d.io.read_triangle_mesh(f"{d}/{f}")
    save(f + ".vertices", np.asarray(m.vertices))
    save(f + ".triangles", np.asarray(m.triangles))
ours = np.load(f"{d}/ours_xyz.npy")
assert ours.dtype == np.float32 and ours.shape == (32768, 3), (ours.dtype, ours.shape)
assert np.array_equal(ours, np.asarray(o3d.io.read_point_cloud(f"{d}/c_bin.pcd").points))
np.save(f"{d}/numpy_xyz.npy", ours)
print("ok")
)";

// Open3D's legacy API holds float64: from binary files exactly our float32 values; from ASCII it
// parses our shortest float32 text as a double, which rounds back to the same float32.
bool SameValue(double v, float ref, bool ascii) {
    return ascii ? static_cast<float>(v) == ref : v == static_cast<double>(ref);
}

void ExpectXyz(const NpyArray& a, const std::string& what) {
    const auto& ref = Reference().xyz;
    const bool ascii = what.find("ascii") != std::string::npos;
    ASSERT_EQ(a.shape, (std::vector<size_t>{ref.size(), 3})) << what;
    for (size_t i = 0; i < ref.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            if (a.dtype == "<f8") {
                ASSERT_TRUE(SameValue(a.As<double>()[3 * i + k], ref[i][k], ascii)) << what << i;
            } else {
                ASSERT_EQ(a.As<float>()[3 * i + k], ref[i][k]) << what << " point " << i;
            }
        }
    }
}

TEST(Open3dInterop, Open3dReadsOurPcdPlyAndMeshesNumpyReadsOurNpy) {
    test::TempDir dir;
    if (RunTool(std::string(kPython) + " -c 'import open3d'", dir / "probe.log") != 0) {
        GTEST_SKIP() << kPython << " cannot import open3d: install the package python3-open3d";
    }
    WritePcd(dir / "c_bin.pcd", Scan(), PcdEncoding::kBinary);
    WritePcd(dir / "c_ascii.pcd", Scan(), PcdEncoding::kAscii);
    WritePly(dir / "c_bin.ply", ToPly(Scan()), PlyEncoding::kBinaryLittleEndian);
    WritePly(dir / "c_ascii.ply", ToPly(Scan()), PlyEncoding::kAscii);
    const common::TriangleMesh mesh = GridMesh();
    WritePly(dir / "m_bin.ply", ToPly(mesh), PlyEncoding::kBinaryLittleEndian);
    WritePly(dir / "m_ascii.ply", ToPly(mesh), PlyEncoding::kAscii);
    std::vector<float> xyz;
    for (const auto& p : Scan().xyz) xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
    WriteNpy(dir / "ours_xyz.npy", NpyArray::From(xyz.data(), {Scan().size(), 3}));
    { std::ofstream(dir / "check.py") << kOpen3dScript; }
    EXPECT_RUNS(std::string(kPython) + " " + Quote(dir / "check.py") + " " + Quote(dir.path()),
                dir.path());

    const size_t n = Reference().size();
    for (const char* f : {"c_bin.pcd", "c_ascii.pcd", "c_bin.ply", "c_ascii.ply"}) {
        const std::string s = f;
        ExpectXyz(ReadNpy(dir / (s + ".legacy.npy")), s + " legacy");
        ExpectXyz(ReadNpy(dir / (s + ".positions.npy")), s + " tensor");
        const NpyArray intensity = ReadNpy(dir / (s + ".intensity.npy"));
        ASSERT_EQ(intensity.ElementCount(), n) << s;
        const NpyArray t = ReadNpy(dir / (s + ".t.npy"));
        ASSERT_EQ(t.ElementCount(), n) << s;
        for (size_t i = 0; i < n; ++i) {
            ASSERT_EQ(intensity.As<float>()[i], Reference().intensity[i]) << s << " " << i;
            ASSERT_EQ(t.As<float>()[i], PcdNsToSeconds(Reference().time_offset_ns[i])) << s;
        }
        // Open3D 0.16's tensor PLY reader skips ushort properties ("unsupported datatype"), so
        // it gets ring from PCD only.
        const bool has_ring = fs::exists(dir / (s + ".ring.npy"));
        EXPECT_EQ(has_ring, s.ends_with(".pcd")) << s;
        if (has_ring) {
            const NpyArray ring = ReadNpy(dir / (s + ".ring.npy"));
            ASSERT_EQ(ring.dtype, "<u2");
            EXPECT_TRUE(
                std::equal(Reference().ring.begin(), Reference().ring.end(), ring.As<uint16_t>()))
                << s;
        }
    }
    for (const char* f : {"m_bin.ply", "m_ascii.ply"}) {
        const std::string s = f;
        const NpyArray v = ReadNpy(dir / (s + ".vertices.npy"));
        const NpyArray t = ReadNpy(dir / (s + ".triangles.npy"));
        ASSERT_EQ(v.shape, (std::vector<size_t>{mesh.vertices.size(), 3})) << s;
        ASSERT_EQ(t.shape, (std::vector<size_t>{mesh.triangles.size(), 3})) << s;
        for (size_t i = 0; i < mesh.vertices.size(); ++i) {
            for (int k = 0; k < 3; ++k) {
                ASSERT_TRUE(SameValue(v.As<double>()[3 * i + k], mesh.vertices[i][k],
                                      s.find("ascii") != std::string::npos))
                    << s << " " << i;
            }
        }
        for (size_t i = 0; i < mesh.triangles.size(); ++i) {
            for (int k = 0; k < 3; ++k) {
                ASSERT_EQ(t.As<int32_t>()[3 * i + k], static_cast<int32_t>(mesh.triangles[i][k]))
                    << s << " " << i;
            }
        }
    }
    // numpy's np.save of the array it loaded from us is byte-identical to our file.
    EXPECT_EQ(ReadFileToString(dir / "numpy_xyz.npy"), ReadFileToString(dir / "ours_xyz.npy"));
}

TEST(CloudCompareInterop, CloudCompareReadsOurPlyCloudsAndMeshes) {
    const fs::path cc = "/usr/bin/CloudCompare";
    if (!fs::exists(cc)) GTEST_SKIP() << cc << " is missing: install the package cloudcompare";
    test::TempDir dir;
    // Headless, CloudCompare loads "intensity" and "scalar_*" properties only (its PLY dialog
    // would offer the others), so ring and t go in as scalar_ring (ushort) and scalar_t (float).
    PlyData cloud = ToPly(Scan());
    cloud.vertex_properties[1].name = "scalar_ring";
    cloud.vertex_properties[2].name = "scalar_t";
    WritePly(dir / "c_bin.ply", cloud, PlyEncoding::kBinaryLittleEndian);
    WritePly(dir / "c_ascii.ply", cloud, PlyEncoding::kAscii);
    const common::TriangleMesh mesh = GridMesh();
    WritePly(dir / "m_bin.ply", ToPly(mesh), PlyEncoding::kBinaryLittleEndian);
    WritePly(dir / "m_ascii.ply", ToPly(mesh), PlyEncoding::kAscii);
    const std::string run = "cd " + Quote(dir.path()) + " && QT_QPA_PLATFORM=offscreen " +
                            Quote(cc) + " -SILENT -AUTO_SAVE OFF ";
    EXPECT_RUNS(run + "-O c_bin.ply -O c_ascii.ply -C_EXPORT_FMT PLY -PLY_EXPORT_FMT BINARY_LE " +
                    "-SAVE_CLOUDS FILE 'cc_c_bin.ply cc_c_ascii.ply'",
                dir.path());
    EXPECT_RUNS(run + "-O m_bin.ply -O m_ascii.ply -M_EXPORT_FMT PLY -PLY_EXPORT_FMT BINARY_LE " +
                    "-SAVE_MESHES FILE 'cc_m_bin.ply cc_m_ascii.ply'",
                dir.path());
    for (const char* f : {"cc_c_bin.ply", "cc_c_ascii.ply"}) {
        const PlyData d = ReadPly(dir / f);
        EXPECT_EQ(d.vertices, Reference().xyz) << f;
        const PlyProperty* intensity = d.Find("scalar_intensity");
        const PlyProperty* ring = d.Find("scalar_ring");
        const PlyProperty* t = d.Find("scalar_t");
        ASSERT_TRUE(intensity && ring && t) << f << ": CloudCompare lost a scalar field";
        EXPECT_EQ(intensity->values, cloud.vertex_properties[0].values) << f;
        EXPECT_EQ(ring->values, cloud.vertex_properties[1].values) << f;
        EXPECT_EQ(t->values, cloud.vertex_properties[2].values) << f;
    }
    for (const char* f : {"cc_m_bin.ply", "cc_m_ascii.ply"}) {
        const common::TriangleMesh back = MeshFromPly(ReadPly(dir / f));
        EXPECT_EQ(back.vertices, mesh.vertices) << f;
        EXPECT_EQ(back.triangles, mesh.triangles) << f;
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::io
