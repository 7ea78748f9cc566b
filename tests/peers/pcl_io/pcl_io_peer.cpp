// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// PCD and PLY through our algorithms/io against PCL's io (libpcl-dev), on the same cloud: the
// measurement behind ARCHITECTURE.md's "What we write by hand" row for the two formats. Prints
// the median, min and max of each side's CPU time over the rounds; each side reads the other's
// file, and a point count that differs is an error (exit 1). README.md says how to build it.
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <time.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <random>
#include <vector>

#include "algorithms/io/pcd.hpp"
#include "algorithms/io/ply.hpp"

// The fields our clouds carry (x y z intensity ring t), as a PCL point type.
struct EIGEN_ALIGN16 ScanPoint {
    PCL_ADD_POINT4D;
    float intensity;
    std::uint16_t ring;
    float t;
    PCL_MAKE_ALIGNED_OPERATOR_NEW
};
POINT_CLOUD_REGISTER_POINT_STRUCT(ScanPoint, (float, x, x)(float, y, y)(float, z, z)(
                                                 float, intensity, intensity)(std::uint16_t, ring,
                                                                              ring)(float, t, t))

namespace {
namespace fs = std::filesystem;
using namespace bimslam;

double ProcessCpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// Seconds of CPU that f took.
template <typename F>
double Cpu(F&& f) {
    const double start = ProcessCpuSeconds();
    f();
    return ProcessCpuSeconds() - start;
}

}  // namespace

int main(int argc, char** argv) {
    const int n = argc > 1 ? std::atoi(argv[1]) : 1000000;
    const int rounds = 7;
    const fs::path dir = fs::temp_directory_path() / "pcl_io_peer";
    fs::create_directories(dir);
    // A 128-ring scan's worth of points many times over, each with intensity, ring and time.
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(-30, 30);
    common::PointCloud ours;
    pcl::PointCloud<ScanPoint> theirs;
    theirs.resize(size_t(n));
    for (int i = 0; i < n; ++i) {
        const Eigen::Vector3f p(u(rng), u(rng), u(rng) / 10);
        const float intensity = std::abs(u(rng)) * 10;
        const auto ring = uint16_t(i % 128);
        const auto t_ns = uint32_t(i % 1024) * 97656u;
        ours.PushBack(p, intensity, ring, t_ns);
        ScanPoint& q = theirs[size_t(i)];
        q.x = p.x(), q.y = p.y(), q.z = p.z(), q.intensity = intensity, q.ring = ring;
        q.t = io::PcdNsToSeconds(t_ns);
    }
    const io::PlyData ply = io::ToPly(ours);
    const char* names[8] = {"PCD write, ours", "PCD write, PCL", "PCD read, ours", "PCD read, PCL",
                            "PLY write, ours", "PLY write, PCL", "PLY read, ours", "PLY read, PCL"};
    std::vector<std::array<double, 8>> times;
    for (int r = 0; r < rounds; ++r) {
        std::array<double, 8> t{};
        size_t ours_read = 0, pcl_read = 0;
        t[0] = Cpu([&] { io::WritePcd(dir / "ours.pcd", ours, io::PcdEncoding::kBinary); });
        t[1] = Cpu([&] { pcl::io::savePCDFileBinary((dir / "pcl.pcd").string(), theirs); });
        t[2] = Cpu([&] { ours_read = io::ReadPcd(dir / "pcl.pcd").size(); });
        t[3] = Cpu([&] {
            pcl::PointCloud<ScanPoint> back;
            pcl::io::loadPCDFile((dir / "ours.pcd").string(), back);
            pcl_read = back.size();
        });
        if (ours_read != size_t(n) || pcl_read != size_t(n)) {
            std::fprintf(stderr, "PCD: read %zu (ours) and %zu (PCL) of %d points\n", ours_read,
                         pcl_read, n);
            return 1;
        }
        t[4] = Cpu([&] { io::WritePly(dir / "ours.ply", ply); });
        t[5] = Cpu([&] { pcl::io::savePLYFileBinary((dir / "pcl.ply").string(), theirs); });
        t[6] = Cpu([&] { ours_read = io::ReadPly(dir / "pcl.ply").vertices.size(); });
        t[7] = Cpu([&] {
            pcl::PointCloud<ScanPoint> back;
            pcl::io::loadPLYFile((dir / "ours.ply").string(), back);
            pcl_read = back.size();
        });
        if (ours_read != size_t(n) || pcl_read != size_t(n)) {
            std::fprintf(stderr, "PLY: read %zu (ours) and %zu (PCL) of %d points\n", ours_read,
                         pcl_read, n);
            return 1;
        }
        times.push_back(t);
    }
    std::printf("%d points (x y z intensity ring t, binary), CPU seconds over %d rounds:\n", n,
                rounds);
    for (size_t k = 0; k < 8; ++k) {
        std::vector<double> v;
        for (const auto& t : times) v.push_back(t[k]);
        std::sort(v.begin(), v.end());
        std::printf("  %-16s median %.3f  min %.3f  max %.3f\n", names[k], v[v.size() / 2],
                    v.front(), v.back());
    }
    fs::remove_all(dir);
    return 0;
}
