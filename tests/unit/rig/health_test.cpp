// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The watchdog's rule (firmware/app/health.hpp, HeartbeatsFresh): WATCHDOG=1 is sent only while
// every thread that has not finished beat within its own stale time. Heartbeats are set by hand
// and `now` is given, so the answer does not depend on the machine's speed.
#include "firmware/app/health.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "firmware/runtime/thread_table.hpp"

namespace bimslam::rig {
namespace {
namespace BIMSLAM_UNITY_ID {

constexpr int64_t kSecond = 1'000'000'000;

// A table of rows that are not started: their stats are the test's to set.
void AddRow(runtime::ThreadTable& t, const std::string& name, int64_t stale_ns) {
    runtime::ThreadSpec spec;
    spec.name = name;
    spec.stale_ns = stale_ns;
    t.Add(spec, [](runtime::ThreadStats&) {});
}

TEST(HeartbeatsFresh, EveryThreadWithinItsStaleTime) {
    runtime::ThreadTable t;
    AddRow(t, "ingest", 2 * kSecond);
    AddRow(t, "odometry", 2 * kSecond);
    const int64_t beat = 1000 * kSecond;
    t.stats(0).heartbeat_ns = beat;
    t.stats(1).heartbeat_ns = beat + kSecond / 2;
    EXPECT_TRUE(HeartbeatsFresh(t, beat + kSecond));
    EXPECT_TRUE(HeartbeatsFresh(t, beat + 2 * kSecond));  // exactly the stale time: still fresh
    // One thread stops beating: 1 ns past its stale time the watchdog is no longer fed.
    EXPECT_FALSE(HeartbeatsFresh(t, beat + 2 * kSecond + 1));
    // It beats again: fed again.
    t.stats(0).heartbeat_ns = beat + 2 * kSecond;
    EXPECT_TRUE(HeartbeatsFresh(t, beat + 2 * kSecond + 1));
}

TEST(HeartbeatsFresh, EachThreadHasItsOwnStaleTime) {
    runtime::ThreadTable t;
    AddRow(t, "writer", 10 * kSecond);  // may block on the disk longer
    AddRow(t, "health", kSecond);
    t.stats(0).heartbeat_ns = 0;
    t.stats(1).heartbeat_ns = 5 * kSecond;
    EXPECT_TRUE(HeartbeatsFresh(t, 6 * kSecond));
    EXPECT_FALSE(HeartbeatsFresh(t, 6 * kSecond + 1));  // health's second ran out
    t.stats(1).heartbeat_ns = 10 * kSecond;
    EXPECT_TRUE(HeartbeatsFresh(t, 10 * kSecond));
    EXPECT_FALSE(HeartbeatsFresh(t, 10 * kSecond + 1));  // the writer's ten ran out
}

// FAULT_THREAD_STALLED names the thread by the same rule, one thread at a time.
TEST(HeartbeatStale, NamesTheThreadThatStoppedBeating) {
    runtime::ThreadTable t;
    AddRow(t, "odometry", 2 * kSecond);
    AddRow(t, "writer", 2 * kSecond);
    t.stats(0).heartbeat_ns = 3 * kSecond;
    t.stats(1).heartbeat_ns = kSecond;
    EXPECT_FALSE(HeartbeatStale(t, 0, 3 * kSecond + 1));
    EXPECT_FALSE(HeartbeatStale(t, 1, 3 * kSecond));  // exactly the stale time
    EXPECT_TRUE(HeartbeatStale(t, 1, 3 * kSecond + 1));
    t.stats(1).finished = true;
    EXPECT_FALSE(HeartbeatStale(t, 1, 100 * kSecond));
}

TEST(HeartbeatsFresh, AFinishedThreadNoLongerCounts) {
    runtime::ThreadTable t;
    AddRow(t, "ingest", kSecond);
    AddRow(t, "lcm", kSecond);
    t.stats(0).heartbeat_ns = 0;  // the replay's ingest ended long ago
    t.stats(1).heartbeat_ns = 100 * kSecond;
    EXPECT_FALSE(HeartbeatsFresh(t, 100 * kSecond));
    t.stats(0).finished = true;
    EXPECT_TRUE(HeartbeatsFresh(t, 100 * kSecond));
}

TEST(HeartbeatsFresh, ARunningThreadThatStopsBeatingGoesStale) {
    // Real threads: one beats until told to stop beating (it then blocks, as a thread stuck on
    // a lock or a disk would), the other beats on. Judged at a `now` past the stuck one's stale
    // time from its last beat, within the other's.
    runtime::ThreadTable t;
    runtime::ThreadSpec stuck;
    stuck.name = "stuck";
    stuck.stale_ns = 3600 * kSecond;  // an hour: however loaded the machine, only `now` decides
    runtime::ThreadSpec alive;
    alive.name = "alive";
    alive.stale_ns = 7200 * kSecond;
    std::atomic<bool> stop_beating{false}, stopped{false}, end{false};
    t.Add(stuck, [&](runtime::ThreadStats& s) {
        while (!stop_beating) s.Beat();
        stopped = true;
        while (!end) std::this_thread::yield();
    });
    t.Add(alive, [&](runtime::ThreadStats& s) {
        while (!end) s.Beat();
    });
    EXPECT_TRUE(t.Start().empty());
    while (t.stats(0).heartbeat_ns == 0 || t.stats(1).heartbeat_ns == 0) std::this_thread::yield();
    EXPECT_TRUE(HeartbeatsFresh(t, runtime::MonotonicNs()));
    stop_beating = true;
    while (!stopped) std::this_thread::yield();
    const int64_t last = t.stats(0).heartbeat_ns;
    EXPECT_TRUE(HeartbeatsFresh(t, last + 3600 * kSecond));
    EXPECT_FALSE(HeartbeatsFresh(t, last + 3600 * kSecond + 1));
    end = true;
    t.Join();
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::rig
