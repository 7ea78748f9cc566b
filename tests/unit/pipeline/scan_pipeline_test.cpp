// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// algorithms/pipeline: which samples reach a scan (IMU by arrival order, Go1 by receive time), the
// clock offset, a clock jump starting the odometry again, keyframes and the configuration check.
#include "algorithms/pipeline/scan_pipeline.hpp"

#include <gtest/gtest.h>

#include "algorithms/common/status.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::pipeline {
namespace {
namespace BIMSLAM_UNITY_ID {

constexpr int64_t kSecond = 1'000'000'000;

ScanInput Scan(int64_t stamp_ns, uint64_t imu_before, int64_t arrival_ns, uint32_t seed) {
    ScanInput s;
    s.cloud = test::MakeRoomScan(32, 512, seed);
    s.cloud.stamp.ns = stamp_ns;
    s.last_column_ns = stamp_ns + kSecond / 10;
    s.last_arrival_ns = arrival_ns;
    s.emitted_arrival_ns = arrival_ns;
    s.imu_before = imu_before;
    return s;
}

odometry::ImuMeasurement Imu(int64_t t) {
    odometry::ImuMeasurement m;
    m.t_ns = t;
    m.accel = {0, 0, 9.81};
    return m;
}

BodyInput Body(int64_t received) {
    BodyInput b;
    b.received_ns = received;
    b.measured_ns = received - 1'000'000;
    return b;
}

TEST(ScanPipeline, SamplesReachTheScanTheyPrecede) {
    ScanPipelineConfig c;
    c.odometry.budget_ms = 1000;
    ScanPipeline p(c);
    const int64_t offset = 1000 * kSecond;  // host minus sensor
    for (int i = 0; i < 15; ++i) p.AddImu(Imu(10 * kSecond + i * 10'000'000));
    for (int i = 0; i < 5; ++i) p.AddBody(Body(offset + 10 * kSecond + i * 30'000'000));
    // The scan was emitted after 10 IMU samples and at host time offset + 10.1 s.
    const ScanOutput& a = p.Process(Scan(10 * kSecond, 10, offset + 10 * kSecond + 100'000'000, 1));
    EXPECT_EQ(a.scan_index, 0u);
    EXPECT_EQ(p.stats().imu_samples, 10u);
    EXPECT_EQ(p.stats().body_samples, 4u);  // received at 0, 30, 60, 90 ms; not 120 ms
    EXPECT_TRUE(p.stats().offset_known);
    EXPECT_EQ(p.stats().host_minus_sensor_ns, offset);
    EXPECT_TRUE(a.keyframe);  // the first scan with points is the first keyframe
    EXPECT_EQ(a.edge, nullptr);
    p.Process(Scan(10 * kSecond + kSecond / 10, 15, offset + 10 * kSecond + 200'000'000, 2));
    EXPECT_EQ(p.stats().imu_samples, 15u);
    EXPECT_EQ(p.stats().body_samples, 5u);
}

TEST(ScanPipeline, ClockJumpStartsTheOdometryAgain) {
    ScanPipelineConfig c;
    c.odometry.budget_ms = 1000;
    ScanPipeline p(c);
    p.Process(Scan(50 * kSecond, 0, 1, 1));
    EXPECT_FALSE(p.Process(Scan(50 * kSecond + kSecond / 10, 0, 2, 2)).clock_jump);
    const ScanOutput& j = p.Process(Scan(3 * kSecond, 0, 3, 3));  // a sensor restart
    EXPECT_TRUE(j.clock_jump);
    EXPECT_EQ(p.stats().clock_jumps, 1u);
    EXPECT_TRUE(j.keyframe);
    EXPECT_EQ(j.keyframe_index, 0u);               // a new segment
    EXPECT_EQ(j.odometry->stamp_ns, 3 * kSecond);  // processed, not ignored as out of order
    EXPECT_TRUE(p.Process(Scan(30 * kSecond, 0, 4, 4)).clock_jump);  // 27 s forward
}

TEST(ScanPipeline, FullPendingRingDropsTheOldestAndCounts) {
    ScanPipelineConfig c;
    c.pending_capacity = 16;
    ScanPipeline p(c);
    for (int i = 0; i < 20; ++i) p.AddImu(Imu(i));
    EXPECT_EQ(p.stats().pending_dropped, 4u);
    EXPECT_EQ(p.imu_added(), 20u);
}

TEST(ScanPipeline, ConfigurationIsChecked) {
    ScanPipelineConfig c;
    c.pending_capacity = 0;
    EXPECT_THROW(ScanPipeline{c}, common::Error);
    c = ScanPipelineConfig{};
    c.clock_jump_forward_s = 0.1;
    EXPECT_THROW(c.Validate(), common::Error);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::pipeline
