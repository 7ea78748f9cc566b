// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/scancontext/candidate_index.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "tests/support/synthetic_scene.hpp"
#include "tests/unit/scancontext/test_clouds.hpp"

namespace bimslam::scancontext {
namespace {
namespace BIMSLAM_UNITY_ID {

using testing::AngleDiff;
using testing::RandomDescriptor;

TEST(CandidateIndexTest, EmptyIndexGivesNoMatch) {
    CandidateIndex index;
    const Descriptor q = RandomDescriptor(20, 60, 1);
    EXPECT_TRUE(index.empty());
    EXPECT_FALSE(index.Query(q).has_value());
    index.Build();
    EXPECT_EQ(index.Indexed(), 0u);
    EXPECT_FALSE(index.Query(q, 5).has_value());
}

TEST(CandidateIndexTest, RejectsDescriptorsOfTheWrongShapeOrWithNonFiniteCells) {
    CandidateIndex index(ScanContextConfig::Indoor());
    const common::Status wrong = index.Add(RandomDescriptor(20, 30, 1));
    EXPECT_EQ(wrong.code(), common::StatusCode::kInvalidArgument);
    EXPECT_NE(wrong.message().find("20 x 30"), std::string::npos) << wrong.message();
    Descriptor nan = RandomDescriptor(20, 60, 2);
    nan(0, 0) = std::numeric_limits<float>::quiet_NaN();
    EXPECT_FALSE(index.Add(nan).ok());
    EXPECT_EQ(index.size(), 0u);

    ASSERT_TRUE(index.Add(RandomDescriptor(20, 60, 3)).ok());
    EXPECT_FALSE(index.Query(RandomDescriptor(10, 60, 3)).has_value());
    EXPECT_FALSE(index.Query(nan).has_value());
    EXPECT_FALSE(index.Query(RandomDescriptor(20, 60, 3), 0).has_value());
    EXPECT_TRUE(index.Query(RandomDescriptor(20, 60, 3), 1).has_value());
}

TEST(CandidateIndexTest, InvalidConfigThrows) {
    ScanContextConfig config;
    config.num_candidates = 0;
    EXPECT_THROW(CandidateIndex{config}, common::Error);
}

// Every entry is found as itself, whether it is in the tree or still pending.
TEST(CandidateIndexTest, FindsStoredEntriesBeforeAndAfterBuild) {
    CandidateIndex index;
    std::vector<Descriptor> stored;
    for (uint32_t i = 0; i < 60; ++i) {
        stored.push_back(RandomDescriptor(20, 60, 100 + i));
        ASSERT_TRUE(index.Add(stored.back()).ok());
        if (i == 29) index.Build();  // half in the tree, half pending
    }
    EXPECT_EQ(index.Indexed(), 30u);
    EXPECT_EQ(index.Pending(), 30u);
    for (size_t i = 0; i < stored.size(); i += 7) {
        const auto m = index.Query(testing::ShiftColumns(stored[i], 11));
        ASSERT_TRUE(m.has_value());
        EXPECT_EQ(m->index, i);
        EXPECT_NEAR(m->distance, 0.0, 1e-6);
        EXPECT_EQ(m->shift, -11);  // entry = query shifted by -11 columns
        EXPECT_EQ(m->candidates.size(), 10u);
        EXPECT_EQ(m->candidates.front().index, i);
        EXPECT_NEAR(m->candidates.front().ring_key_distance, 0.0, 1e-5);
        for (size_t c = 1; c < m->candidates.size(); ++c) {
            EXPECT_LE(m->candidates[c - 1].ring_key_distance, m->candidates[c].ring_key_distance);
        }
    }
    index.Build();
    EXPECT_EQ(index.Pending(), 0u);
    const auto m = index.Query(stored[45], 3);
    ASSERT_TRUE(m.has_value());
    EXPECT_EQ(m->index, 45u);
    EXPECT_EQ(m->candidates.size(), 3u);
}

// The tree must not point into storage that later Adds reallocate (ASan would catch it) and must
// keep answering for the entries it holds.
TEST(CandidateIndexTest, SurvivesManyAddsAfterBuild) {
    CandidateIndex index(ScanContextConfig::Indoor());
    std::vector<Descriptor> stored;
    for (uint32_t i = 0; i < 2000; ++i) {
        stored.push_back(RandomDescriptor(20, 60, 1000 + i));
        ASSERT_TRUE(index.Add(stored.back()).ok());
        if (i == 9 || i == 700) index.Build();
    }
    for (size_t i : {3u, 500u, 1500u, 1999u}) {
        const auto m = index.Query(stored[i]);
        ASSERT_TRUE(m.has_value());
        EXPECT_EQ(m->index, i);
    }
    index.Build();
    CandidateIndex moved = std::move(index);
    const auto m = moved.Query(stored[1234]);
    ASSERT_TRUE(m.has_value());
    EXPECT_EQ(m->index, 1234u);
}

TEST(CandidateIndexTest, ExcludesTheMostRecentEntries) {
    CandidateIndex index;
    std::vector<Descriptor> stored;
    for (uint32_t i = 0; i < 40; ++i) {
        stored.push_back(RandomDescriptor(20, 60, 200 + i));
        ASSERT_TRUE(index.Add(stored.back()).ok());
        if (i == 34) index.Build();  // 35 in the tree, 5 pending
    }
    // Query with the latest entry, leaving out the last 10: 30..39 may not appear.
    for (size_t exclude : {1u, 3u, 10u, 39u}) {
        const auto m = index.Query(stored[39], 10, exclude);
        ASSERT_TRUE(m.has_value()) << exclude;
        const size_t eligible = 40 - exclude;
        EXPECT_LT(m->index, eligible);
        EXPECT_EQ(m->candidates.size(), std::min<size_t>(10, eligible));
        for (const Candidate& c : m->candidates) EXPECT_LT(c.index, eligible);
    }
    // An entry that is not excluded is still found.
    const auto m = index.Query(stored[20], 10, 10);
    ASSERT_TRUE(m.has_value());
    EXPECT_EQ(m->index, 20u);
    EXPECT_FALSE(index.Query(stored[0], 10, 40).has_value());
    EXPECT_FALSE(index.Query(stored[0], 10, 1000).has_value());
}

// Place recognition among many different synthetic places: each query re-scans place j from a
// pose moved by `displacement` metres in a random horizontal direction and turned by a random
// heading psi, with range noise and columns not aligned with the stored scan; it must find j,
// with the heading to within one sector.
struct Database {
    std::vector<test::Place> places;
    CandidateIndex index;
};

test::LidarModel RetrievalLidar() {
    test::LidarModel lidar;  // OS1-32 vertical field of view, coarser in azimuth to stay fast
    lidar.columns = 360;
    lidar.range_noise_sigma = 0.01;
    return lidar;
}

Database MakeDatabase(const ScanContextConfig& config, test::Place (*make_place)(uint32_t),
                      int num_places, uint32_t seed) {
    Database db{{}, CandidateIndex(config)};
    DescriptorBuilder builder(config);
    Descriptor d;
    for (int i = 0; i < num_places; ++i) {
        db.places.push_back(make_place(seed + static_cast<uint32_t>(i)));
        const Eigen::Isometry3d T(Eigen::Translation3d(db.places.back().sensor));
        builder.Build(
            test::ScanScene(db.places.back().scene, T, RetrievalLidar(), static_cast<uint32_t>(i)),
            &d);
        EXPECT_TRUE(db.index.Add(d).ok());
    }
    db.index.Build();
    return db;
}

struct RetrievalResult {
    int queries = 0;
    int correct = 0;
    int yaw_within_sector = 0;  // among the correct ones
};

RetrievalResult RunQueries(const Database& db, double displacement, int num_queries,
                           uint32_t seed) {
    const ScanContextConfig& config = db.index.config();
    DescriptorBuilder builder(config);
    Descriptor d;
    std::mt19937 rng(seed);
    std::uniform_int_distribution<size_t> pick(0, db.places.size() - 1);
    std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi);
    std::set<size_t> asked;
    RetrievalResult result;
    while (result.queries < num_queries) {
        const size_t j = pick(rng);
        if (!asked.insert(j).second) continue;
        const double psi = angle(rng), dir = angle(rng);
        const Eigen::Vector3d offset =
            displacement * Eigen::Vector3d(std::cos(dir), std::sin(dir), 0.0);
        // T_world_query: the place's sensor moved and turned by psi.
        const Eigen::Isometry3d T = Eigen::Translation3d(db.places[j].sensor + offset) *
                                    Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitZ());
        test::LidarModel lidar = RetrievalLidar();
        lidar.azimuth_offset_rad = angle(rng);
        builder.Build(
            test::ScanScene(db.places[j].scene, T, lidar, static_cast<uint32_t>(100000 + j)), &d);
        const auto m = db.index.Query(d);
        ++result.queries;
        if (!m || m->index != j) continue;
        ++result.correct;
        // entry ~= Rz(yaw) * query, and T_entry_query has yaw psi (see Match::yaw).
        if (std::abs(AngleDiff(m->yaw, psi)) <= config.SectorAngle()) ++result.yaw_within_sector;
    }
    std::cout << "[ scancontext ] " << ToString(config.kind) << ", " << db.places.size()
              << " places, query " << displacement << " m away: " << result.correct << "/"
              << result.queries << " found, " << result.yaw_within_sector
              << " of them with the yaw within one sector\n";
    return result;
}

// Indoors, rings are 0.5 m wide, so a 0.2 m move carries a wall into the next ring in roughly a
// quarter of the sectors, and the sparse z-span descriptor (mostly one wall cell per sector) feels
// it: over 200 queries we measured 92 % found at 0.2 m and 99.5 % at 0.1 m (with the same rooms,
// the max-height rule reaches 97 % at 0.2 m; see the report of this change). The bounds below are
// those measurements less one or two queries of 50.
TEST(CandidateIndexTest, FindsTheRightRoomAmongAThousand) {
    const Database db = MakeDatabase(ScanContextConfig::Indoor(), &test::MakeRandomRoom, 1000, 7);
    const RetrievalResult near = RunQueries(db, 0.1, 50, 8);
    EXPECT_GE(near.correct, 49);
    EXPECT_GE(near.yaw_within_sector, near.correct - 1);
    const RetrievalResult far = RunQueries(db, 0.2, 50, 9);
    EXPECT_GE(far.correct, 45);
    EXPECT_GE(far.yaw_within_sector, far.correct - 2);
    RecordProperty("found_at_0_1_m", near.correct);
    RecordProperty("found_at_0_2_m", far.correct);
}

// Outdoors (4 m rings) the same search is insensitive to such moves: 200/200 in our runs at 0.2 m
// and at 1 m among 1000 places.
TEST(CandidateIndexTest, FindsTheRightTownPlace) {
    const Database db = MakeDatabase(ScanContextConfig::Outdoor(), &test::MakeRandomTown, 300, 17);
    const RetrievalResult near = RunQueries(db, 0.2, 50, 18);
    EXPECT_GE(near.correct, 50);
    EXPECT_EQ(near.yaw_within_sector, near.correct);
    const RetrievalResult far = RunQueries(db, 1.0, 50, 19);
    EXPECT_GE(far.correct, 49);
    EXPECT_GE(far.yaw_within_sector, far.correct - 1);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::scancontext
