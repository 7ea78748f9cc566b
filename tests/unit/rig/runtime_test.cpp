// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// firmware/runtime: the SPSC queue (order, full, two threads), the seqlock, the wake-up, the
// sd_notify protocol against a socket the test binds, heartbeats.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <thread>

#include "firmware/runtime/sd_notify.hpp"
#include "firmware/runtime/seqlock.hpp"
#include "firmware/runtime/spsc_queue.hpp"
#include "firmware/runtime/thread_table.hpp"
#include "firmware/runtime/wakeup.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::runtime {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(SpscQueue, FifoFullAndDrops) {
    SpscQueue<int> q("q", 3, [](int& v) { v = -1; });
    EXPECT_EQ(q.capacity(), 3u);
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(q.TryPush(i));
    EXPECT_FALSE(q.TryPush(99));  // full: the new item is dropped and counted
    EXPECT_EQ(q.drops(), 1u);
    EXPECT_EQ(q.size(), 3u);
    for (int i = 0; i < 3; ++i) {
        ASSERT_NE(q.Front(), nullptr);
        EXPECT_EQ(*q.Front(), i);
        q.Pop();
    }
    EXPECT_EQ(q.Front(), nullptr);
    const QueueStats s = q.Stats();
    EXPECT_EQ(s.max_depth, 3u);
    EXPECT_EQ(s.pushed, 3u);
}

TEST(SpscQueue, TwoThreadsLoseNothingWhenTheConsumerKeepsUp) {
    Wakeup wakeup;
    SpscQueue<uint64_t> q("q", 64, {}, &wakeup);
    constexpr uint64_t kItems = 50000;
    std::thread producer([&] {
        for (uint64_t i = 0; i < kItems;) {
            if (uint64_t* slot = q.BeginPush()) {
                *slot = i++;
                q.CommitPush();
            } else {
                std::this_thread::yield();  // full: two shared cores
            }
        }
    });
    uint64_t expected = 0;
    while (expected < kItems) {
        const uint32_t seen = wakeup.Sequence();
        if (uint64_t* v = q.Front()) {
            ASSERT_EQ(*v, expected);
            ++expected;
            q.Pop();
        } else {
            wakeup.Wait(seen, 1'000'000);
        }
    }
    producer.join();
    EXPECT_EQ(q.drops(), 0u);
}

TEST(Seqlock, ReadersSeeWholeValues) {
    struct Pair {
        uint64_t a = 0, b = 0;
    };
    Seqlock<Pair> lock;
    std::atomic<bool> stop{false};
    std::thread writer([&] {
        for (uint64_t i = 1; !stop; ++i) lock.Store({i, i});
    });
    for (int i = 0; i < 100000; ++i) {
        const Pair p = lock.Load();
        ASSERT_EQ(p.a, p.b);
    }
    stop = true;
    writer.join();
}

TEST(Wakeup, WaitReturnsOnNotifyOrTimeout) {
    Wakeup w;
    const uint32_t seen = w.Sequence();
    const int64_t t0 = MonotonicNs();
    w.Wait(seen, 20'000'000);
    EXPECT_GE(MonotonicNs() - t0, 15'000'000);  // nothing notified: the timeout
    std::thread t([&] { w.Notify(); });
    t.join();
    // Notified since `seen`: returns at once. A Wait that slept instead would hang this test
    // for an hour, past ctest's timeout: a failure that needs no clock to see.
    w.Wait(seen, int64_t(3600) * 1'000'000'000);
    EXPECT_NE(w.Sequence(), seen);
}

TEST(SdNotifier, SendsToTheNotifySocketAndNothingWithout) {
    ::unsetenv("NOTIFY_SOCKET");
    {
        SdNotifier none;
        EXPECT_FALSE(none.enabled());
        EXPECT_FALSE(none.Notify("READY=1"));
    }
    test::TempDir dir;
    const std::string path = (dir / "notify").string();
    const int fd = ::socket(AF_UNIX, SOCK_DGRAM, 0);
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    std::strncpy(a.sun_path, path.c_str(), sizeof(a.sun_path) - 1);
    ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)), 0);
    ::setenv("NOTIFY_SOCKET", path.c_str(), 1);
    ::setenv("WATCHDOG_USEC", "3000000", 1);
    SdNotifier n;
    EXPECT_TRUE(n.enabled());
    EXPECT_EQ(n.watchdog_ns(), 3'000'000'000);
    EXPECT_TRUE(n.Notify("READY=1\nSTATUS=up"));
    char buf[64] = {};
    EXPECT_EQ(::recv(fd, buf, sizeof(buf), 0), 17);
    EXPECT_STREQ(buf, "READY=1\nSTATUS=up");
    ::close(fd);
    ::unsetenv("NOTIFY_SOCKET");
    ::unsetenv("WATCHDOG_USEC");
}

TEST(ThreadTable, RunsRowsAndReportsCycles) {
    ThreadTable t;
    std::atomic<int> ran{0};
    ThreadSpec spec;
    spec.name = "worker";
    spec.deadline_ns = 1'000'000;
    t.Add(spec, [&](ThreadStats& s) {
        s.Cycle(500'000, 1'000'000);
        s.Cycle(2'000'000, 1'000'000);  // a miss
        ++ran;
    });
    EXPECT_TRUE(t.Start().empty());  // priority 0, any CPU: nothing to refuse
    t.Join();
    EXPECT_EQ(ran, 1);
    EXPECT_EQ(t.stats(0).cycles, 2u);
    EXPECT_EQ(t.stats(0).deadline_misses, 1u);
    EXPECT_EQ(t.stats(0).max_cycle_ns, 2'000'000);
    EXPECT_TRUE(t.stats(0).finished);
    EXPECT_NE(t.Describe().find("worker"), std::string::npos);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::runtime
