// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The rig's map package (algorithms/localization/rig_map.hpp): a round trip keeps every field and
// registers a query exactly as the pyramid it was made from; a damaged, cut, foreign, newer or
// oversized file is refused naming the file and what is wrong.
#include "algorithms/localization/rig_map.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <fstream>
#include <iostream>
#include <random>
#include <string>

#include "algorithms/common/status.hpp"
#include "algorithms/registration/oriented_cloud.hpp"
#include "algorithms/scancontext/config.hpp"
#include "algorithms/simulation/lidar_simulator.hpp"
#include "tests/support/test_support.hpp"
#include "tests/unit/odometry/odometry_scenes.hpp"

namespace bimslam::localization {
namespace {
namespace BIMSLAM_UNITY_ID {

using odometry::test::Pose;

common::PointCloud RoomScan(const simulation::Scene& scene, const Eigen::Isometry3d& T,
                            uint64_t seed) {
    return odometry::test::Scan(
        scene, [&](double) { return T; }, 0, seed, simulation::NoiseModel::Noiseless());
}

// Two reference keyframes in the furnished room, on two storeys 0.5 m apart, with their
// descriptors and the pyramid the anchoring would build from them.
struct Made {
    RigMap map;
    registration::SurfelPyramid pyramid{registration::RegistrationConfig{}};
};
Made MakeMap() {
    const simulation::Scene scene(odometry::test::FurnishedRoom());
    Made m;
    m.map.model_file = "room.ifc";
    m.map.model_sha256 = std::string(64, 'a');
    m.map.created = "2026-12-03T10:00:00Z";
    m.map.reference = "out/reference";
    m.map.storeys = {{"Ground", "0aBcD", 0.0}, {"Upper", "1xYz", 0.5}};
    const scancontext::ScanContextConfig sc = scancontext::ScanContextConfig::Indoor();
    m.map.descriptor.rings = sc.num_rings;
    m.map.descriptor.sectors = sc.num_sectors;
    m.map.descriptor.max_radius_m = sc.max_radius;
    m.map.descriptor.min_points = sc.indoor_min_points;
    m.map.descriptor.min_z_span_m = sc.indoor_min_z_span;
    scancontext::DescriptorBuilder builder(sc);
    registration::OrientedCloudConfig oc;
    oc.sample_voxel_size = 0.05;
    for (const Eigen::Isometry3d& T : {Pose(-2, 0, 0.6, 0), Pose(2, 0.5, 0.4, 1.0)}) {
        const common::PointCloud scan = RoomScan(scene, T, m.map.keyframes.size() + 100);
        m.map.keyframes.push_back(T);
        m.map.keyframe_storey.push_back(StoreyAt(m.map.storeys, T.translation().z()));
        m.map.descriptors.emplace_back();
        builder.Build(scan, &m.map.descriptors.back());
        m.pyramid.Add(registration::MakeOrientedCloud(scan, oc), T);
    }
    m.pyramid.Build();
    m.pyramid.mutable_level(1).MarkPorous({0, 2});  // registration/free_space.hpp
    for (size_t l = 0; l < m.pyramid.levels(); ++l) m.map.levels.push_back(m.pyramid.level(l));
    // One space: a 2 x 1 m room as two triangles, 0 to 3 m high, on the ground storey.
    RigMapSpace room;
    room.name = "Room 1";
    room.global_id = "3vB2YO$MX4xv5uCqZZG05x";
    room.storey = 0;
    room.z_max = 3;
    room.triangles = {{0, 0}, {2, 0}, {2, 1}, {0, 0}, {2, 1}, {0, 1}};
    m.map.spaces = {room};
    return m;
}

TEST(RigMap, ARoundTripKeepsEveryFieldAndRegistersAsThePyramidItCameFrom) {
    const Made made = MakeMap();
    const RigMap& a = made.map;
    ASSERT_EQ(a.keyframe_storey, (std::vector<int32_t>{1, 0}));
    test::TempDir dir;
    WriteRigMap(dir / "office.rigmap", a);
    const RigMap b = ReadRigMap(dir / "office.rigmap");
    EXPECT_EQ(b.model_file, a.model_file);
    EXPECT_EQ(b.model_sha256, a.model_sha256);
    EXPECT_EQ(b.frame, "bim");
    EXPECT_EQ(b.created, a.created);
    EXPECT_EQ(b.reference, a.reference);
    EXPECT_EQ(b.sensor.model, a.sensor.model);
    EXPECT_EQ(b.descriptor.kind, a.descriptor.kind);
    ASSERT_EQ(b.storeys.size(), 2u);
    EXPECT_EQ(b.storeys[1].name, "Upper");
    EXPECT_EQ(b.storeys[1].global_id, "1xYz");
    EXPECT_EQ(b.storeys[1].elevation_m, 0.5);
    EXPECT_EQ(b.keyframe_storey, a.keyframe_storey);
    ASSERT_EQ(b.keyframes.size(), 2u);
    for (size_t k = 0; k < 2; ++k) {
        EXPECT_TRUE(b.keyframes[k].isApprox(a.keyframes[k], 1e-12));
        EXPECT_TRUE(b.descriptors[k] == a.descriptors[k]);
        EXPECT_GT(a.descriptors[k].sum(), 0.0f);
    }
    ASSERT_EQ(b.spaces.size(), 1u);
    EXPECT_EQ(b.spaces[0].name, "Room 1");
    EXPECT_EQ(b.spaces[0].global_id, a.spaces[0].global_id);
    EXPECT_EQ(b.spaces[0].triangles, a.spaces[0].triangles);
    EXPECT_TRUE(b.levels.at(1).surfels().at(2).porous);
    EXPECT_FALSE(b.levels.at(1).surfels().at(1).porous);
    ASSERT_EQ(b.levels.size(), a.levels.size());
    for (size_t l = 0; l < a.levels.size(); ++l) {
        ASSERT_GT(a.levels[l].size(), 10u);
        ASSERT_EQ(b.levels[l].size(), a.levels[l].size());
        EXPECT_EQ(b.levels[l].config().voxel_size, a.levels[l].config().voxel_size);
        EXPECT_TRUE(b.levels[l].surfels() == a.levels[l].surfels());
    }
    // A query registered to the restored pyramid lands exactly where it lands on the original.
    const simulation::Scene scene(odometry::test::FurnishedRoom());
    const Eigen::Isometry3d truth = Pose(0.7, -0.6, 0.45, 0.25, 0.02, -0.015);
    const registration::OrientedCloud query =
        registration::MakeOrientedCloud(RoomScan(scene, truth, 7), {});
    const registration::RegistrationConfig config;
    const auto r1 = registration::Register(query, made.pyramid, Pose(0, 0, 0.6, 0), config);
    const auto r2 = registration::Register(query, b.Pyramid(), Pose(0, 0, 0.6, 0), config);
    EXPECT_FALSE(r1.failed);
    EXPECT_LT((r1.T_target_source.translation() - truth.translation()).norm(), 0.01);
    EXPECT_TRUE(r2.T_target_source.matrix() == r1.T_target_source.matrix());
    EXPECT_EQ(r2.fitness.inliers, r1.fitness.inliers);
}

// The message names the file and says `what`.
void ExpectRefused(const std::filesystem::path& path, const std::string& what,
                   size_t max_bytes = kRigMapMaxBytes) {
    try {
        ReadRigMap(path, max_bytes);
        ADD_FAILURE() << path << " was read";
    } catch (const common::FileError& e) {
        EXPECT_EQ(e.path(), path.string());
        EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
}

void Put(const std::filesystem::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
}

TEST(RigMap, ADamagedCutForeignNewerOrOversizedFileIsRefusedNamingIt) {
    const std::string good = SerializeRigMap(MakeMap().map);
    test::TempDir dir;
    const auto path = dir / "map.rigmap";

    std::string damaged = good;
    damaged[good.size() / 2] ^= 0x10;
    Put(path, damaged);
    ExpectRefused(path, "damaged");

    Put(path, good.substr(0, good.size() - 100));
    ExpectRefused(path, "(cut off)");

    Put(path, "");
    ExpectRefused(path, "too short");

    std::string foreign = good;
    foreign[0] = 'X';
    Put(path, foreign);
    ExpectRefused(path, "not a bimslam rig map");

    // Version 2 with a header whose own CRC-32 is right: refused for its version, not as damage.
    std::string newer = good;
    newer[8] = 2;
    const uint32_t crc =
        uint32_t(crc32(crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(newer.data()), 28));
    std::memcpy(newer.data() + 28, &crc, 4);
    Put(path, newer);
    ExpectRefused(path, "rig map version 2; this build reads version 1");

    Put(path, good);
    ExpectRefused(path, "more than the 1000 a rig map may hold", 1000);
    EXPECT_EQ(ReadRigMap(path).keyframes.size(), 2u);
}

// `bytes` with its two CRC-32s made good again (rig_map.cpp: of the body at 24, of the header at
// 28), so that the parser itself meets what was changed.
std::string WithGoodChecksums(std::string bytes) {
    const auto crc = [](std::string_view b) {
        return uint32_t(
            crc32(crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(b.data()), uInt(b.size())));
    };
    const uint32_t body = crc(std::string_view(bytes).substr(32));
    std::memcpy(bytes.data() + 24, &body, 4);
    const uint32_t header = crc(std::string_view(bytes).substr(0, 28));
    std::memcpy(bytes.data() + 28, &header, 4);
    return bytes;
}

// A surfel's porous flag (byte 13 of its record, reserved before, so 0 in older packages) other
// than 0 or 1 is refused, naming the surfel; 1 is read as porous.
TEST(RigMap, APorousFlagOtherThanZeroOrOneIsRefused) {
    const std::string good = SerializeRigMap(MakeMap().map);
    const size_t surf = good.find("SURF");
    ASSERT_NE(surf, std::string::npos);
    const size_t flag = surf + 16 + 8 + 13;  // section header, count, the first surfel's byte 13
    ASSERT_EQ(good[flag], 0);
    const auto with_flag = [&](char value) {
        std::string bytes = good;
        bytes[flag] = value;
        return WithGoodChecksums(bytes);
    };
    EXPECT_TRUE(ParseRigMap("flag.rigmap", with_flag(1)).levels.at(0).surfels().at(0).porous);
    try {
        ParseRigMap("flag.rigmap", with_flag(2));
        ADD_FAILURE() << "a porous flag of 2 was read";
    } catch (const common::FileError& e) {
        EXPECT_NE(std::string(e.what()).find("surfel 0 of level 0: porous flag 2"),
                  std::string::npos)
            << e.what();
    }
}

// Mutants whose CRC-32s are made good again, so that the parser itself meets the damage (a
// mutant of the bytes alone stops at the checksum): each is read or refused with a FileError
// naming the file, never a crash or another exception (and under no sanitizer here: the
// localization library is not in the ASan build, toolchain/README.md).
TEST(RigMap, MutantsWithGoodChecksumsAreReadOrRefusedNamingTheFile) {
    const std::string good = SerializeRigMap(MakeMap().map);
    constexpr size_t kHeader = 32;  // rig_map.cpp: CRC-32 of the body at 24, of the header at 28
    std::mt19937 rng(35);
    size_t accepted = 0, refused = 0;
    for (int i = 0; i < 3000; ++i) {
        const std::string bytes = WithGoodChecksums(good.substr(0, kHeader) +
                                                    test::Mutate(good.substr(kHeader), rng, 512));
        try {
            ParseRigMap("mutant.rigmap", bytes);
            ++accepted;
        } catch (const common::FileError& e) {
            ++refused;
            ASSERT_NE(std::string(e.what()).find("mutant.rigmap"), std::string::npos) << e.what();
        } catch (const std::exception& e) {
            FAIL() << "mutant " << i << ": " << e.what();
        }
    }
    std::cout << accepted << " mutants read, " << refused << " refused\n";
    EXPECT_GT(refused, 100u);
}

TEST(RigMap, TheWriterRefusesCountsThatDisagree) {
    RigMap m = MakeMap().map;
    m.descriptors.pop_back();
    EXPECT_THROW(SerializeRigMap(m), common::Error);
    m = MakeMap().map;
    m.keyframe_storey[0] = 2;  // two storeys: 0 and 1
    EXPECT_THROW(SerializeRigMap(m), common::Error);
    m = MakeMap().map;
    m.descriptors[0].resize(3, 4);
    EXPECT_THROW(SerializeRigMap(m), common::Error);
    m = MakeMap().map;
    m.descriptor.min_points = 0;  // no Scan Context the rig could make
    EXPECT_THROW(SerializeRigMap(m), common::Error);
}

TEST(RigMap, APointIsInTheSpaceWhoseFootprintAndHeightsHoldIt) {
    const RigMap m = MakeMap().map;
    EXPECT_EQ(SpaceAt(m, {1.5, 0.2, 0.5}), 0);   // in the first triangle
    EXPECT_EQ(SpaceAt(m, {0.1, 0.9, 2.9}), 0);   // in the second
    EXPECT_EQ(SpaceAt(m, {2.5, 0.5, 0.5}), -1);  // beside it
    EXPECT_EQ(SpaceAt(m, {1.0, 0.5, 3.5}), -1);  // above it
}

TEST(RigMap, AKeyframeIsOnTheHighestStoreyAtOrBelowIt) {
    const std::vector<RigMapStorey> storeys = {{"G", "", 0.0}, {"1", "", 3.0}, {"2", "", 6.0}};
    EXPECT_EQ(StoreyAt(storeys, -0.5), -1);
    EXPECT_EQ(StoreyAt(storeys, 0.6), 0);
    EXPECT_EQ(StoreyAt(storeys, 3.0), 1);
    EXPECT_EQ(StoreyAt(storeys, 7.5), 2);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::localization
