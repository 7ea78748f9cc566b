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
#include <functional>
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

// One format's four steps: each side writes the cloud, and reads the file the other wrote.
struct Format {
    const char* name;
    std::function<void()> write_ours, write_pcl;
    std::function<size_t()> read_ours, read_pcl;  // the points read
};

// One round of `format`: the CPU seconds of its four steps into t[0..3]. False, said on stderr,
// when a side read another number of points than n.
bool Round(const Format& format, size_t n, double* t) {
    size_t ours_read = 0, pcl_read = 0;
    t[0] = Cpu(format.write_ours);
    t[1] = Cpu(format.write_pcl);
    t[2] = Cpu([&] { ours_read = format.read_ours(); });
    t[3] = Cpu([&] { pcl_read = format.read_pcl(); });
    if (ours_read == n && pcl_read == n) return true;
    std::fprintf(stderr, "%s: read %zu (ours) and %zu (PCL) of %zu points\n", format.name,
                 ours_read, pcl_read, n);
    return false;
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
    const auto pcl_count = [](auto load, const fs::path& path) {
        pcl::PointCloud<ScanPoint> back;
        load(path.string(), back);
        return back.size();
    };
    const Format formats[2] = {
        {"PCD", [&] { io::WritePcd(dir / "ours.pcd", ours, io::PcdEncoding::kBinary); },
         [&] { pcl::io::savePCDFileBinary((dir / "pcl.pcd").string(), theirs); },
         [&] { return io::ReadPcd(dir / "pcl.pcd").size(); },
         [&] { return pcl_count(pcl::io::loadPCDFile<ScanPoint>, dir / "ours.pcd"); }},
        {"PLY", [&] { io::WritePly(dir / "ours.ply", ply); },
         [&] { pcl::io::savePLYFileBinary((dir / "pcl.ply").string(), theirs); },
         [&] { return io::ReadPly(dir / "pcl.ply").vertices.size(); },
         [&] { return pcl_count(pcl::io::loadPLYFile<ScanPoint>, dir / "ours.ply"); }}};
    // Per format: write ours, write PCL's, read PCL's with ours, read ours with PCL.
    std::vector<std::array<double, 8>> times;
    for (int r = 0; r < rounds; ++r) {
        std::array<double, 8> t{};
        for (size_t f = 0; f < 2; ++f) {
            if (!Round(formats[f], size_t(n), &t[4 * f])) return 1;
        }
        times.push_back(t);
    }
    std::printf("%d points (x y z intensity ring t, binary), CPU seconds over %d rounds:\n", n,
                rounds);
    const char* steps[4] = {"write, ours", "write, PCL", "read, ours", "read, PCL"};
    for (size_t k = 0; k < 8; ++k) {
        std::vector<double> v;
        for (const auto& t : times) v.push_back(t[k]);
        std::sort(v.begin(), v.end());
        std::printf("  %s %-12s median %.3f  min %.3f  max %.3f\n", formats[k / 4].name,
                    steps[k % 4], v[v.size() / 2], v.front(), v.back());
    }
    fs::remove_all(dir);
    return 0;
}
