// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/changes/dbscan.hpp"

#include <gtest/gtest.h>

#include <map>
#include <random>

#include "algorithms/common/status.hpp"

namespace bimslam::changes {
namespace {
namespace BIMSLAM_UNITY_ID {

// Textbook DBSCAN by brute force (O(n^2)): core points and their clusters.
std::vector<int> ReferenceCoreClusters(const std::vector<Eigen::Vector3f>& p, float eps,
                                       int min_pts, std::vector<uint8_t>* core) {
    const size_t n = p.size();
    core->assign(n, 0);
    for (size_t i = 0; i < n; ++i) {
        int c = 0;
        for (size_t j = 0; j < n; ++j) c += (p[i] - p[j]).norm() <= eps;
        (*core)[i] = c >= min_pts;
    }
    std::vector<int> label(n, -1);
    int next = 0;
    for (size_t i = 0; i < n; ++i) {
        if (!(*core)[i] || label[i] >= 0) continue;
        std::vector<size_t> stack = {i};
        label[i] = next;
        while (!stack.empty()) {
            const size_t a = stack.back();
            stack.pop_back();
            for (size_t b = 0; b < n; ++b) {
                if ((*core)[b] && label[b] < 0 && (p[a] - p[b]).norm() <= eps) {
                    label[b] = next;
                    stack.push_back(b);
                }
            }
        }
        ++next;
    }
    return label;
}

TEST(Dbscan, AgreesWithTheTextbookAlgorithmOnCoreAndBorderPoints) {
    std::mt19937 rng(3);
    std::normal_distribution<float> g(0, 0.15f);
    std::uniform_real_distribution<float> u(-2, 2);
    std::vector<Eigen::Vector3f> p;
    for (int c = 0; c < 6; ++c) {
        const Eigen::Vector3f centre(u(rng), u(rng), u(rng));
        for (int k = 0; k < 120; ++k) p.push_back(centre + Eigen::Vector3f(g(rng), g(rng), g(rng)));
    }
    for (int k = 0; k < 200; ++k) p.emplace_back(u(rng), u(rng), u(rng));  // noise
    const DbscanConfig config{0.12, 6};
    const DbscanResult r = Dbscan(p, config);
    std::vector<uint8_t> core;
    const std::vector<int> ref = ReferenceCoreClusters(p, 0.12f, 6, &core);
    // Core points: the same partition (labels may be numbered differently).
    std::map<int, int> to_ref, from_ref;
    size_t cores = 0;
    for (size_t i = 0; i < p.size(); ++i) {
        if (!core[i]) continue;
        ++cores;
        ASSERT_GE(r.labels[i], 0);
        const auto [a, fa] = to_ref.emplace(r.labels[i], ref[i]);
        const auto [b, fb] = from_ref.emplace(ref[i], r.labels[i]);
        EXPECT_EQ(a->second, ref[i]);
        EXPECT_EQ(b->second, r.labels[i]);
    }
    EXPECT_EQ(r.core_points, cores);
    EXPECT_EQ(size_t(r.clusters), to_ref.size());
    EXPECT_GE(r.clusters, 6);
    // Border points: in the cluster of a core point within eps; noise: no core point within eps.
    for (size_t i = 0; i < p.size(); ++i) {
        if (core[i]) continue;
        bool near_core = false;
        for (size_t j = 0; j < p.size(); ++j) {
            if (core[j] && (p[i] - p[j]).norm() <= 0.12f) {
                near_core = true;
                if (r.labels[i] == r.labels[j]) break;
            }
        }
        EXPECT_EQ(r.labels[i] >= 0, near_core) << i;
    }
}

TEST(Dbscan, LabelsDoNotDependOnThreadsAndCountTheFirstCorePointFirst) {
    std::vector<Eigen::Vector3f> p;
    for (int k = 0; k < 50; ++k) p.emplace_back(5 + 0.01f * float(k), 0, 0);  // cluster A
    for (int k = 0; k < 50; ++k) p.emplace_back(0.01f * float(k), 0, 0);      // cluster B
    p.emplace_back(10, 10, 10);                                               // noise
    const DbscanResult r = Dbscan(p, DbscanConfig{0.05, 3});
    EXPECT_EQ(r.clusters, 2);
    EXPECT_EQ(r.labels[0], 0);
    EXPECT_EQ(r.labels[50], 1);
    EXPECT_EQ(r.labels[100], -1);
}

TEST(Dbscan, EmptyInputAndBadConfig) {
    EXPECT_EQ(Dbscan({}, DbscanConfig{}).clusters, 0);
    EXPECT_THROW(Dbscan({}, DbscanConfig{0, 5}), common::Error);
    EXPECT_THROW(Dbscan({}, DbscanConfig{0.1, 0}), common::Error);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::changes
