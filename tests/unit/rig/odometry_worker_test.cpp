// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The odometry thread's end of a replay (firmware/modules/odometry_worker.hpp): lossless to the
// last scan. When the recording ends the rig stops its sources, and the worker still has scans
// queued; their outputs must wait for the (paced) LCM thread as every other output does. The
// worker once gave up on a full output queue as soon as the sources stopped: `bimslam-rig replay
// --speed max` then lost the last keyframe on LCM in 2 of 12 runs (queue drops 1).
#include "firmware/modules/odometry_worker.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "firmware/runtime/spsc_queue.hpp"
#include "firmware/runtime/wakeup.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::rig {
namespace {
namespace BIMSLAM_UNITY_ID {

constexpr int64_t kSecond = 1'000'000'000;
constexpr int kScans = 6;

TEST(OdometryWorker, AReplayKeepsEveryOutputOfTheScansLeftWhenTheSourcesStop) {
    runtime::Wakeup wakeup, out_wakeup;
    runtime::SpscQueue<ScanSlot> scans("scans", kScans, {}, &wakeup);
    runtime::SpscQueue<ImuItem> imu("imu", 4, {}, &wakeup);
    runtime::SpscQueue<BodyItem> bodies("go1_samples", 4, {}, &wakeup);
    // One slot each and no consumer yet: the first scan's outputs fill them.
    runtime::SpscQueue<OdometryItem> odometry_out("odometry_out", 1, {}, &out_wakeup);
    runtime::SpscQueue<KeyframeItem> keyframes_lcm("keyframes_lcm", 1, {}, &out_wakeup);
    runtime::SpscQueue<KeyframeItem> keyframes_session("keyframes_session", 1, {}, &out_wakeup);
    runtime::SpscQueue<PoseItem> poses("poses", 1, {}, &out_wakeup);
    OdometryWorkerConfig config;
    config.lossless = true;  // a replay
    config.record = false;   // no session writer: poses and keyframes_session stay unused
    OdometryWorker worker(config,
                          WorkerQueues{scans, imu, bodies, odometry_out, keyframes_lcm,
                                       keyframes_session, poses, wakeup},
                          nullptr);
    for (int i = 0; i < kScans; ++i) {
        ScanSlot* slot = scans.BeginPush();
        ASSERT_NE(slot, nullptr);
        slot->scan.cloud = test::MakeRoomScan(32, 512, uint32_t(i + 1));
        slot->scan.cloud.stamp.ns = 10 * kSecond + i * kSecond / 10;
        slot->scan.last_column_ns = slot->scan.cloud.stamp.ns + kSecond / 10;
        slot->scan.emitted_arrival_ns = slot->scan.last_column_ns;
        scans.CommitPush();
    }
    // The recording has ended and the sources are stopped before the worker takes its first scan.
    const std::atomic<bool> stop{true}, inputs_done{true};
    std::atomic<bool> worker_done{false};
    std::thread thread([&] {
        runtime::ThreadStats stats;
        worker.Run(stats, stop, inputs_done);
        worker_done.store(true);
    });
    // The consumer comes late, as a paced LCM thread does, and then takes everything.
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    int odometry = 0, keyframes = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (std::chrono::steady_clock::now() < deadline) {
        const bool done = worker_done.load();  // before the last look at the queues
        for (; odometry_out.Front() != nullptr; odometry_out.Pop()) ++odometry;
        for (; keyframes_lcm.Front() != nullptr; keyframes_lcm.Pop()) ++keyframes;
        if (done) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_TRUE(worker_done.load()) << "the worker did not finish within 60 s";
    thread.join();
    EXPECT_EQ(odometry, kScans);
    EXPECT_GE(keyframes, 1);  // the first scan is a keyframe
    EXPECT_EQ(worker.counters().scans, uint64_t(kScans));
    EXPECT_EQ(worker.counters().keyframes, uint64_t(keyframes));
    EXPECT_EQ(worker.counters().outputs_dropped, 0u);
    EXPECT_EQ(odometry_out.Stats().drops + keyframes_lcm.Stats().drops, 0u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::rig
