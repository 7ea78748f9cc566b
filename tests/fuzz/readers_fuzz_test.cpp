// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Long mutation-fuzz runs of every reader (label `fuzz`, not part of `make test`; `make fuzz`
// runs them under AddressSanitizer + UndefinedBehaviorSanitizer). Each reader must only ever
// return a value or throw common::FileError naming the input. The unit tests run short versions
// of the same loops on every `make test`.
#include <gtest/gtest.h>

#include <cstdlib>
#include <functional>
#include <random>

#include "algorithms/common/se3.hpp"
#include "algorithms/io/g2o.hpp"
#include "algorithms/io/las.hpp"
#include "algorithms/io/npy.hpp"
#include "algorithms/io/pcd.hpp"
#include "algorithms/io/ply.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/io/trajectory.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::io {
namespace {

// BIMSLAM_FUZZ_ITERATIONS mutations per seed (default 5000: brief, as ctest runs it).
int Iterations() {
    const char* env = std::getenv("BIMSLAM_FUZZ_ITERATIONS");
    return env && *env ? std::max(1, std::atoi(env)) : 5'000;
}

void Fuzz(const std::string& name, const std::vector<std::string>& seeds,
          const std::function<void(const std::string&)>& parse) {
    std::vector<test::FuzzSeed> fuzz_seeds;
    for (const std::string& s : seeds) fuzz_seeds.push_back({s, 256});
    const auto counts = test::FuzzReader(name, fuzz_seeds, Iterations(),
                                         static_cast<uint32_t>(std::hash<std::string>{}(name)),
                                         test::kMutationBytes, parse);
    std::cout << name << ": " << counts.accepted << " mutants accepted, " << counts.rejected
              << " rejected\n";
    EXPECT_GT(counts.rejected, 0u);
}

std::vector<StampedPose> Trajectory() {
    std::vector<StampedPose> out;
    for (int i = 0; i < 5; ++i) {
        common::Vector6d xi;
        xi << i, 2.0 * i, 0.1, 0.1 * i, -0.2, 0.3;
        out.push_back(StampedPose::FromIsometry(1'700'000'000'000'000'000 + i * 100'000'000,
                                                common::ExpSE3(xi)));
    }
    return out;
}

TEST(Fuzz, Pcd) {
    const auto cloud = test::MakeRoomScan(2, 8, 1);
    Fuzz("f.pcd",
         {SerializePcd(cloud, PcdEncoding::kBinary), SerializePcd(cloud, PcdEncoding::kAscii)},
         [](const std::string& b) { ParsePcd("f.pcd", b); });
}

TEST(Fuzz, Ply) {
    PlyData mesh = ToPly(test::MakeRoomScan(2, 4, 2));
    mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
    Fuzz("f.ply",
         {SerializePly(mesh, PlyEncoding::kBinaryLittleEndian),
          SerializePly(mesh, PlyEncoding::kAscii)},
         [](const std::string& b) { ParsePly("f.ply", b); });
}

TEST(Fuzz, Las) {
    LasData las;
    LasExtraField distance{"distance", LasType::kFloat32, "m", 1e9, {}};
    for (int i = 0; i < 6; ++i) {
        las.xyz.push_back(Eigen::Vector3d(i, 2.0 * i, 0.5));
        las.classification.push_back(uint8_t(6 + i));
        las.gps_time.push_back(4.8e8 + i);
        distance.values.push_back(0.01 * i);
    }
    las.extra = {distance};
    Fuzz("f.las", {SerializeLas(las)}, [](const std::string& b) { ParseLas("f.las", b); });
}

TEST(Fuzz, Npy) {
    const float v[] = {1.5f, -2.0f, 3.25f, 4.0f, 5.0f, 6.0f};
    Fuzz("f.npy", {SerializeNpy(NpyArray::From(v, {2, 3}))},
         [](const std::string& b) { ParseNpy("f.npy", b); });
}

TEST(Fuzz, TextFormats) {
    const auto traj = Trajectory();
    std::vector<Eigen::Isometry3d> poses;
    for (const auto& p : traj) poses.push_back(p.Pose());
    Fuzz("f.tum", {SerializeTum(traj)}, [](const std::string& b) { ParseTum("f.tum", b); });
    Fuzz("f.txt", {SerializeKitti(poses)}, [](const std::string& b) { ParseKitti("f.txt", b); });
    G2oGraph g{
        poses,
        {SessionEdge{0, 1, common::Between(poses[0], poses[1]), common::Matrix6d::Identity()}}};
    Fuzz("f.g2o", {SerializeG2o(g)}, [](const std::string& b) { ParseG2o("f.g2o", b); });
    Fuzz("session.json", {SerializeManifest(SessionManifest{})},
         [](const std::string& b) { ParseManifest("session.json", b); });
}

}  // namespace
}  // namespace bimslam::io
