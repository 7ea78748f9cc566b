// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The rig map package's reader on bytes that come from outside (algorithms/localization/
// rig_map.hpp), built and run under ASan and UBSan (label `sanitized`): a small package made here
// without the simulator, then cut and mutated with its header made to agree, so that the section
// parser, not the CRC, meets the damage. Whatever the bytes, the reader returns a package or
// throws common::FileError naming it; nothing else. The round trip on a simulated room and the
// refusals' words are in rig_map_test.cpp (Release).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/localization/rig_map.hpp"
#include "algorithms/registration/oriented_cloud.hpp"
#include "algorithms/scancontext/config.hpp"
#include "tests/support/rig_map_bytes.hpp"

namespace bimslam::localization {
namespace {
namespace BIMSLAM_UNITY_ID {

// A corner of a room (floor and two walls, 2 m each, points every 5 cm) seen from `at`.
std::vector<Eigen::Vector3f> Corner(const Eigen::Vector3f& at) {
    std::vector<Eigen::Vector3f> points;
    for (int i = 0; i < 40; ++i) {
        for (int k = 0; k < 40; ++k) {
            const float u = 0.05f * float(i), v = 0.05f * float(k);
            points.emplace_back(Eigen::Vector3f(u, v, 0.0f) - at);
            points.emplace_back(Eigen::Vector3f(u, 0.0f, v) - at);
            points.emplace_back(Eigen::Vector3f(0.0f, u, v) - at);
        }
    }
    return points;
}

// Two keyframes on two storeys, small descriptors, two surfel levels, one space: every section.
RigMap SmallRigMap() {
    RigMap m;
    m.model_file = "corner.ifc";
    m.model_sha256 = std::string(64, 'c');
    m.created = "2026-12-04T08:00:00Z";
    m.reference = "reference";
    m.storeys = {{"Ground", "0aBcD", 0.0}, {"Upper", "1xYz", 3.0}};
    const scancontext::ScanContextConfig sc = scancontext::ScanContextConfig::Indoor();
    m.descriptor.rings = 4;
    m.descriptor.sectors = 8;
    m.descriptor.max_radius_m = sc.max_radius;
    m.descriptor.min_points = sc.indoor_min_points;
    m.descriptor.min_z_span_m = sc.indoor_min_z_span;
    for (int k = 0; k < 2; ++k) {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.translation() << 1.0 + k, 1.0, 0.6 + 3.0 * k;
        m.keyframes.push_back(T);
        m.keyframe_storey.push_back(k);
        scancontext::Descriptor d(4, 8);
        for (int c = 0; c < 32; ++c) d.data()[c] = 0.1f * float(c + k);
        m.descriptors.push_back(d);
    }
    const registration::OrientedCloud cloud =
        registration::MakeOrientedCloud(Corner(Eigen::Vector3f(1, 1, 0.6)), {});
    for (const double voxel : {1.0, 0.5}) {
        registration::SurfelMapConfig c;
        c.voxel_size = voxel;
        registration::SurfelMap level(c);
        level.Add(cloud, m.keyframes[0]);
        level.Build();
        m.levels.push_back(std::move(level));
    }
    RigMapSpace room;
    room.name = "Room 1";
    room.global_id = "3vB2YO$MX4xv5uCqZZG05x";
    room.storey = 0;
    room.z_max = 3;
    room.triangles = {{0, 0}, {2, 0}, {2, 2}, {0, 0}, {2, 2}, {0, 2}};
    m.spaces = {room};
    return m;
}

// Parses `bytes` (header made to agree); true when read, false when refused with a FileError
// naming `name`. Any other exception fails the test.
bool ReadOrRefused(std::string bytes) {
    test::MakeRigMapHeaderAgree(&bytes);
    try {
        ParseRigMap("mutant.rigmap", bytes);
        return true;
    } catch (const common::FileError& e) {
        EXPECT_EQ(e.path(), "mutant.rigmap");
        return false;
    }
}

TEST(RigMapRead, ASmallPackageReadsBack) {
    const RigMap a = SmallRigMap();
    ASSERT_GT(a.levels[0].size(), 0u);
    ASSERT_GT(a.levels[1].size(), a.levels[0].size());
    const RigMap b = ParseRigMap("small.rigmap", SerializeRigMap(a));
    EXPECT_EQ(b.model_file, a.model_file);
    EXPECT_EQ(b.storeys.size(), 2u);
    EXPECT_EQ(b.keyframe_storey, a.keyframe_storey);
    ASSERT_EQ(b.descriptors.size(), 2u);
    EXPECT_TRUE(b.descriptors[1] == a.descriptors[1]);
    ASSERT_EQ(b.levels.size(), 2u);
    EXPECT_EQ(b.levels[1].size(), a.levels[1].size());
    ASSERT_EQ(b.spaces.size(), 1u);
    EXPECT_EQ(b.spaces[0].triangles, a.spaces[0].triangles);
}

// The helper computes the header the writer does (its size and CRC-32s are a copy of the
// format's, rig_map.cpp): a package it seals again is unchanged to the byte, so the cuts and
// mutants below reach the section parser instead of all stopping at the checksums.
TEST(RigMapRead, TheHeaderHelperSealsAsTheWriterDoes) {
    const std::string bytes = SerializeRigMap(SmallRigMap());
    std::string sealed = bytes;
    sealed[24] ^= 0x5a;  // both CRC-32s and the size spoilt
    sealed[28] ^= 0x5a;
    sealed[16] ^= 0x01;
    test::MakeRigMapHeaderAgree(&sealed);
    EXPECT_EQ(sealed, bytes);
}

// Every length from the header's end on: the sections are cut wherever the cut falls.
TEST(RigMapRead, EveryCutIsRefused) {
    const std::string bytes = SerializeRigMap(SmallRigMap());
    size_t read = 0;
    for (size_t n = 0; n < bytes.size(); ++n) read += ReadOrRefused(bytes.substr(0, n));
    EXPECT_EQ(read, 0u) << "a package cut short was read";
}

// Each byte replaced by random ones, one at a time and eight at a time (2000 mutants each): a
// flip in a float may still be a package; nothing may crash or be read out of bounds.
TEST(RigMapRead, MutatedBytesAreReadOrRefusedNeverMisread) {
    const std::string bytes = SerializeRigMap(SmallRigMap());
    std::mt19937 rng(7);
    std::uniform_int_distribution<size_t> at(8, bytes.size() - 1);  // past the magic
    std::uniform_int_distribution<int> value(0, 255);
    size_t refused = 0, read = 0;
    for (const int flips : {1, 8}) {
        for (int k = 0; k < 2000; ++k) {
            std::string m = bytes;
            for (int f = 0; f < flips; ++f) m[at(rng)] = char(value(rng));
            const bool ok = ReadOrRefused(m);
            refused += !ok;
            read += ok;
        }
    }
    EXPECT_GT(refused, 100u) << "the mutants reached the checks";
    EXPECT_GT(read, 100u) << "the mutants got past the checksums (a flip in a float still reads)";
}

// The fuzz target's seed (tests/fuzz/corpus/rig_map_fuzz) is a package this build reads. It is
// written again by `BIMSLAM_WRITE_FUZZ_SEEDS=1 sanitized_test --gtest_filter=RigMapRead.*`
// after a format change.
TEST(RigMapRead, TheFuzzSeedIsAPackage) {
    const std::filesystem::path seed =
        std::filesystem::path(BIMSLAM_SOURCE_ROOT) / "tests/fuzz/corpus/rig_map_fuzz/small.rigmap";
    if (std::getenv("BIMSLAM_WRITE_FUZZ_SEEDS")) WriteRigMap(seed, SmallRigMap());
    const RigMap m = ReadRigMap(seed);
    EXPECT_EQ(m.keyframes.size(), 2u);
    EXPECT_EQ(m.levels.size(), 2u);
    EXPECT_EQ(m.spaces.size(), 1u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::localization
