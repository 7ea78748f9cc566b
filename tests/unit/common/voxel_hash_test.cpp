// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/common/voxel_hash.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <vector>

namespace bimslam::common {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(VoxelHash, KeysUnpackAndSortByXThenYThenZ) {
    // changes::PointGrid finds a column's cells between the keys of its lowest and highest z.
    const std::vector<Eigen::Vector3i> sorted = {{-kVoxelIndexLimit, 5, 5},
                                                 {-1, kVoxelIndexLimit, 0},
                                                 {0, -3, 7},
                                                 {0, -2, -kVoxelIndexLimit},
                                                 {0, -2, -1},
                                                 {0, -2, 0},
                                                 {0, -2, 1},
                                                 {1, -kVoxelIndexLimit, -kVoxelIndexLimit},
                                                 {kVoxelIndexLimit, 0, 0}};
    for (size_t i = 0; i < sorted.size(); ++i) {
        const uint64_t key = PackVoxel(sorted[i]);
        EXPECT_EQ(UnpackVoxel(key), sorted[i]);
        EXPECT_EQ(key >> 63, 0u) << "a voxel key must never be the table's empty marker";
        if (i > 0) {
            EXPECT_LT(PackVoxel(sorted[i - 1]), key) << i;
        }
    }
}

TEST(VoxelHash, VoxelOfFloorsAndClampsIntoThePackableRange) {
    EXPECT_EQ(VoxelOf(Eigen::Vector3f(0.5f, -0.5f, -1.0f)), Eigen::Vector3i(0, -1, -1));
    EXPECT_EQ(VoxelOf(Eigen::Vector3f(1e9f, -1e9f, 2.0f)),
              Eigen::Vector3i(kVoxelIndexLimit, -kVoxelIndexLimit, 2));
    // 0.1 m voxels: the key is the voxel's, by multiplying with the inverse size.
    const Eigen::Vector3f p(1.26f, -0.04f, 3.0f);
    EXPECT_EQ(VoxelKey(p, 10.0f), PackVoxel(Eigen::Vector3i(12, -1, 30)));
}

// VoxelOf's one-conversion floor is std::floor, clamped into the packable range, point for
// point: below and above zero, on voxel faces, at the range's edge and beyond it.
TEST(VoxelHash, VoxelOfIsTheClampedFloor) {
    const float limit = float(kVoxelIndexLimit);
    const auto reference = [&](const Eigen::Vector3f& p) {
        Eigen::Vector3i v;
        for (int k = 0; k < 3; ++k) v[k] = int(std::clamp(std::floor(p[k]), -limit, limit));
        return v;
    };
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> coord(-120.f, 120.f);
    for (const float inv : {1.0f / 0.01f, 1.0f / 0.1f, 1.0f / 0.35f, 1.0f, 0.5f}) {
        for (int i = 0; i < 20000; ++i) {
            const Eigen::Vector3f p = Eigen::Vector3f(coord(rng), coord(rng), coord(rng)) * inv;
            ASSERT_EQ(VoxelOf(p), reference(p)) << p.transpose() << " " << inv;
        }
    }
    for (const float x : {0.0f, -0.0f, 1.0f, -1.0f, -2.5f, 2.5f, -1e-7f, 1e-7f, limit - 1,
                          -(limit - 1), limit, -limit, limit + 8, -limit - 8, 1e9f, -1e9f}) {
        const Eigen::Vector3f p(x, -x, 0.3f);
        EXPECT_EQ(VoxelOf(p), reference(p)) << x;
    }
}

TEST(VoxelHash, BehavesAsAMapThroughGrowthAndClear) {
    VoxelHash table(4);  // small: the inserts below rehash it several times
    std::map<uint64_t, uint32_t> truth;
    std::mt19937_64 rng(7);
    std::uniform_int_distribution<int> axis(-50, 50);
    for (uint32_t i = 0; i < 5000; ++i) {
        const uint64_t key =
            PackVoxel(Eigen::Vector3i(axis(rng), axis(rng), axis(rng) / 10));  // clustered
        bool fresh = false;
        uint32_t& value = table.FindOrInsert(key, i, &fresh);
        const auto [it, expected_fresh] = truth.try_emplace(key, i);
        EXPECT_EQ(fresh, expected_fresh);
        EXPECT_EQ(value, it->second);
        value += 1;  // the reference is the stored value
        it->second += 1;
    }
    EXPECT_EQ(table.size(), truth.size());
    for (const auto& [key, value] : truth) EXPECT_EQ(table.Find(key), value);
    EXPECT_EQ(table.Find(PackVoxel(Eigen::Vector3i(99, 99, 99))), VoxelHash::kAbsent);

    std::map<uint64_t, uint32_t> seen;
    table.ForEach(
        [&](uint64_t key, uint32_t value) { EXPECT_TRUE(seen.emplace(key, value).second); });
    EXPECT_EQ(seen, truth);

    table.Clear();
    EXPECT_EQ(table.size(), 0u);
    EXPECT_EQ(table.Find(truth.begin()->first), VoxelHash::kAbsent);
    size_t entries = 0;
    table.ForEach([&](uint64_t, uint32_t) { ++entries; });
    EXPECT_EQ(entries, 0u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::common
