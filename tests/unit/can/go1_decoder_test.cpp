// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/can/go1_decoder.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "algorithms/common/status.hpp"
#include "drivers/can/crc8.hpp"
#include "tests/unit/can/go1_stream.hpp"

namespace bimslam::can {
namespace {
namespace BIMSLAM_UNITY_ID {

using common::CanFrame;
using testing::MakeStream;
using testing::Stream;

// Feeds every frame; returns every sample emitted, in order.
std::vector<Go1Sample> FeedAll(Go1Decoder& d, const std::vector<CanFrame>& frames) {
    std::vector<Go1Sample> out;
    for (const CanFrame& f : frames) {
        const Go1FeedResult r = d.Feed(f);
        EXPECT_EQ(r.samples, static_cast<int>(d.ready().size()));
        out.insert(out.end(), d.ready().begin(), d.ready().end());
    }
    return out;
}

// Index into st.frames of message `id` of sample `sample` (copy 0 or 1 for the 5 ms ones).
size_t FrameOf(const Stream& st, size_t sample, uint32_t id, int copy = 0) {
    for (size_t i = 0; i < st.frames.size(); ++i) {
        if (st.sample_of_frame[i] == sample && st.frames[i].id == id && copy-- == 0) return i;
    }
    ADD_FAILURE() << "no frame " << id << " in sample " << sample;
    return 0;
}

// Rewrites a frame's alive counter (with a correct CRC, as a bridge would send it).
void SetCounter(CanFrame& f, uint8_t counter) {
    f.data[1] = static_cast<uint8_t>((f.data[1] & 0xF0) | counter);
    f.data[0] = Go1FrameCrc(f.id, f.data.data());
}

uint64_t SumOfVerdicts(const Go1DecoderStats& s) {
    uint64_t sum = 0;
    for (int v = 0; v <= static_cast<int>(Go1Verdict::kLate); ++v) {
        sum += s.Count(static_cast<Go1Verdict>(v));
    }
    return sum;
}

TEST(Go1Decoder, DecodesWhatTheEncoderSentAcrossTheBridgeClockWrap) {
    // The bridge clock starts 1 s before its 32-bit microseconds wrap.
    const int64_t wrap_ns = (int64_t{1} << 32) * 1000;
    const Stream st = MakeStream(500, 1, 2'000'000'000, wrap_ns - 1'000'000'000);
    Go1Decoder dec;
    const std::vector<Go1Sample> out = FeedAll(dec, st.frames);
    ASSERT_EQ(out.size(), st.samples.size());
    for (size_t i = 0; i < out.size(); ++i) {
        SCOPED_TRACE(i);
        const Go1Sample& got = out[i];
        const Go1Sample& truth = st.samples[i];
        EXPECT_EQ(got.counter, i % 15);
        EXPECT_EQ(got.fresh, st.groups[i]);
        EXPECT_EQ(got.valid, kAllGroups);
        EXPECT_EQ(got.host_time_ns, st.last_frame_ns[i]);  // emitted at its last due frame
        EXPECT_EQ(got.bridge_time_ns, truth.bridge_time_ns / 1000 * 1000);  // unwrapped
        testing::ExpectSameValues(got, truth, st.groups[i]);
        if (::testing::Test::HasFailure()) break;
    }
    const Go1DecoderStats& s = dec.stats();
    EXPECT_EQ(s.frames, st.frames.size());
    EXPECT_EQ(s.samples, 500u);
    EXPECT_EQ(s.samples_incomplete, 0u);
    EXPECT_EQ(s.duplicate, 2u * 500);  // the second copy of GYRO and ACCEL per sample
    EXPECT_EQ(s.accepted, s.frames - s.duplicate);
    EXPECT_EQ(s.Faults(), 0u);
    EXPECT_EQ(s.counter_lost + s.timeout + s.sna + s.not_valid + s.out_of_range, 0u);
    EXPECT_EQ(SumOfVerdicts(s), s.frames);
}

TEST(Go1Decoder, EmitsEachSampleOnceAtItsLastDueFrame) {
    const Stream st = MakeStream(3, 2);
    Go1Decoder dec;
    for (size_t i = 0; i < st.frames.size(); ++i) {
        const Go1FeedResult r = dec.Feed(st.frames[i]);
        const size_t sample = st.sample_of_frame[i];
        const bool last_of_burst =
            i + 1 == st.frames.size() ||
            st.frames[i + 1].timestamp_ns - st.frames[i].timestamp_ns > testing::kSpacingNs;
        const bool first_tick = st.frames[i].timestamp_ns <
                                1'000'000'000 + (2 * int64_t(sample) + 1) * testing::kTickNs;
        if (first_tick && last_of_burst) {
            ASSERT_EQ(r.samples, 1) << i;
            EXPECT_EQ(dec.ready()[0].counter, sample);
            EXPECT_EQ(r.verdict, Go1Verdict::kAccepted);
        } else {
            ASSERT_EQ(r.samples, 0) << i;
            EXPECT_EQ(r.verdict, first_tick ? Go1Verdict::kAccepted : Go1Verdict::kDuplicate);
        }
    }
    EXPECT_EQ(dec.Flush(), 0);  // nothing pending
    EXPECT_EQ(dec.Tick(st.frames.back().timestamp_ns + 8'000'000), 0);
}

TEST(Go1Decoder, ForeignAndMalformedFramesAreCountedAndChangeNothing) {
    Stream st = MakeStream(10, 3);
    const Stream clean = st;
    std::vector<CanFrame> junk;
    CanFrame f = st.frames[FrameOf(st, 3, 0x100)];
    CanFrame foreign = f;
    foreign.id = 0x123;
    junk.push_back(foreign);
    CanFrame ext = f;
    ext.extended = true;  // 0x100 as a 29-bit id is another identifier
    junk.push_back(ext);
    CanFrame remote = f;
    remote.remote = true;
    remote.len = 0;
    junk.push_back(remote);
    CanFrame fd = f;
    fd.fd = true;
    junk.push_back(fd);
    CanFrame error{};
    error.error = true;
    error.id = 0x100;
    junk.push_back(error);
    CanFrame short_frame = f;
    short_frame.len = 7;
    junk.push_back(short_frame);
    CanFrame long_frame = f;
    long_frame.len = 12;
    junk.push_back(long_frame);
    const size_t at = FrameOf(st, 3, 0x0F0);
    st.frames.insert(st.frames.begin() + at, junk.begin(), junk.end());
    Go1Decoder dec;
    const auto out = FeedAll(dec, st.frames);
    Go1Decoder ref;
    const auto want = FeedAll(ref, clean.frames);
    ASSERT_EQ(out.size(), want.size());
    for (size_t i = 0; i < out.size(); ++i) {
        EXPECT_EQ(out[i].counter, want[i].counter);
        EXPECT_EQ(out[i].fresh, want[i].fresh);
        EXPECT_EQ(out[i].vx, want[i].vx);
    }
    const Go1DecoderStats& s = dec.stats();
    EXPECT_EQ(s.foreign_id, 2u);
    EXPECT_EQ(s.bad_frame, 2u);
    EXPECT_EQ(s.error_frame, 1u);
    EXPECT_EQ(s.bad_dlc, 2u);
    EXPECT_EQ(s.frames, ref.stats().frames + 7);
    EXPECT_EQ(SumOfVerdicts(s), s.frames);
}

TEST(Go1Decoder, CrcMismatchDropsTheFrameAndTheSecondCopyStandsIn) {
    Stream st = MakeStream(10, 4);
    st.frames[FrameOf(st, 5, 0x110, 0)].data[4] ^= 0x10;  // first GYRO copy of sample 5
    st.frames[FrameOf(st, 6, 0x100)].data[0] ^= 0x01;     // BODY_VEL of sample 6: the CRC byte
    Go1Decoder dec;
    const auto out = FeedAll(dec, st.frames);
    ASSERT_EQ(out.size(), 10u);
    EXPECT_EQ(dec.stats().crc, 2u);
    EXPECT_TRUE(out[5].fresh & kGroupGyro);  // from the copy 5 ms later, which completed it
    EXPECT_EQ(out[5].host_time_ns, st.frames[FrameOf(st, 5, 0x110, 1)].timestamp_ns);
    testing::ExpectSameValues(out[5], st.samples[5], kGroupGyro);
    EXPECT_FALSE(out[6].fresh & kGroupBodyVel);  // sample 6 went out without it
    EXPECT_TRUE(out[6].valid & kGroupBodyVel);   // still valid: the value of sample 5, held
    EXPECT_EQ(out[6].vx, out[5].vx);
    EXPECT_EQ(dec.stats().samples_incomplete, 1u);
    EXPECT_EQ(dec.stats().counter_lost, 1u);  // BODY_VEL of sample 7: step 2
    EXPECT_EQ(dec.stats().duplicate, 2u * 10 - 1);
}

TEST(Go1Decoder, RepeatsAreDroppedButThePlannedSecondCopyIsNot) {
    Stream st = MakeStream(10, 5);
    const size_t bvel = FrameOf(st, 4, 0x100);
    st.frames.insert(st.frames.begin() + bvel + 1, st.frames[bvel]);  // a 10 ms frame twice
    const size_t gyro = FrameOf(st, 6, 0x110, 1);
    st.frames.insert(st.frames.begin() + gyro + 1, st.frames[gyro]);  // a third GYRO copy
    Go1Decoder dec;
    const auto out = FeedAll(dec, st.frames);
    EXPECT_EQ(out.size(), 10u);
    EXPECT_EQ(dec.stats().counter_repeat, 2u);
    EXPECT_EQ(dec.stats().duplicate, 2u * 10);
    EXPECT_EQ(dec.stats().samples_incomplete, 0u);
    // Counter 15 is never sent.
    CanFrame f = st.frames[FrameOf(st, 9, 0x0F0)];
    SetCounter(f, 15);
    EXPECT_EQ(dec.Feed(f).verdict, Go1Verdict::kCounterInvalid);
    EXPECT_EQ(dec.stats().counter_invalid, 1u);
}

TEST(Go1Decoder, LostSampleIsAcceptedAndCounted) {
    Stream st = MakeStream(12, 6);
    std::vector<CanFrame> kept;
    for (size_t i = 0; i < st.frames.size(); ++i) {
        if (st.sample_of_frame[i] != 5) kept.push_back(st.frames[i]);
    }
    Go1Decoder dec;
    const auto out = FeedAll(dec, kept);
    ASSERT_EQ(out.size(), 11u);
    EXPECT_EQ(out[5].counter, 6);
    EXPECT_EQ(out[5].valid, kAllGroups);
    EXPECT_EQ(out[5].fresh, st.groups[6]);  // BODY_STATE etc. due again with sample 6
    // The 10 ms messages: step 2. The 5 ms ones were not seen for 15 ms + their place in the
    // burst, more than their GenMsgTimeout (3 x 5 ms): timed out, back at once.
    EXPECT_EQ(dec.stats().counter_lost, 4u);
    EXPECT_EQ(dec.stats().timeout, 2u);
    EXPECT_EQ(dec.stats().Faults(), 0u);
    EXPECT_EQ(dec.stats().samples_incomplete, 0u);
}

TEST(Go1Decoder, CounterJumpResynchronisesAfterTwoGoodFrames) {
    // From sample 5 on the bridge's counter is 3 ahead (a restart, say).
    Stream st = MakeStream(30, 7);
    for (size_t i = 0; i < st.frames.size(); ++i) {
        const size_t n = st.sample_of_frame[i];
        if (n >= 5) SetCounter(st.frames[i], static_cast<uint8_t>((n + 3) % 15));
    }
    Go1Decoder dec;
    const auto out = FeedAll(dec, st.frames);
    const Go1DecoderStats& s = dec.stats();
    // Every-sample messages: jump at sample 5, first good frame at 6 (dropped), accepted from 7.
    // 20 ms messages: jump at 6, good at 8, accepted from 10. STATUS: jump at 10, good at 20.
    EXPECT_EQ(s.counter_resync, 6u + 3u + 1u);
    EXPECT_EQ(s.resyncing, 6u + 3u + 1u);
    ASSERT_EQ(out.size(), 5u + 23u);  // samples 5 and 6 had no accepted frame
    EXPECT_EQ(out[5].counter, (7 + 3) % 15);
    const uint16_t slow = kGroupBodyState | kGroupOdomXy | kGroupOdomZYaw;
    for (size_t i = 5; i < out.size(); ++i) {
        const size_t n = i + 2;  // sample index
        uint16_t want = kAllGroups;
        if (n < 10) want &= ~slow;           // still resynchronising
        if (n >= 10) want &= ~kGroupStatus;  // jumped at 10, not accepted again by 29
        EXPECT_EQ(out[i].valid, want) << "sample " << n;
    }
    EXPECT_EQ(SumOfVerdicts(s), s.frames);
}

TEST(Go1Decoder, TimeoutInvalidatesAGroupUntilItReturns) {
    Stream st = MakeStream(30, 8);
    std::vector<CanFrame> kept;
    for (size_t i = 0; i < st.frames.size(); ++i) {
        const size_t n = st.sample_of_frame[i];
        if (!(st.frames[i].id == 0x112 && n >= 10 && n < 20)) kept.push_back(st.frames[i]);
    }
    Go1Decoder dec;
    const auto out = FeedAll(dec, kept);
    ASSERT_EQ(out.size(), 30u);
    EXPECT_EQ(dec.stats().timeout, 1u);
    for (size_t n = 0; n < 30; ++n) {
        // Timed out 30 ms after its last frame (sample 9): during sample 12's burst.
        const bool timed_out = n >= 12 && n < 20;
        EXPECT_EQ((out[n].valid & kGroupQuat) == 0, timed_out) << n;
        EXPECT_EQ((out[n].fresh & kGroupQuat) != 0, n < 10 || n >= 20) << n;
    }
    // Samples 10 and 11 waited for QUAT in vain; from 12 on it is not due (three samples
    // behind: its next frame is a fresh start, not a step the sequence predicts).
    EXPECT_EQ(dec.stats().samples_incomplete, 2u);
    EXPECT_EQ(dec.timed_out(), 0);
}

TEST(Go1Decoder, TickNoticesSilenceAndEmitsOverdueSamples) {
    Stream st = MakeStream(5, 9);
    // Sample 4 without GO1_FOOT; the stream stops after sample 4's first tick.
    std::vector<CanFrame> frames;
    for (size_t i = 0; i < st.frames.size(); ++i) {
        const bool repeat_of_4 = st.sample_of_frame[i] == 4 &&
                                 st.frames[i].timestamp_ns >= 1'000'000'000 + 9 * testing::kTickNs;
        if (st.frames[i].id != 0x120 || st.sample_of_frame[i] != 4) {
            if (!repeat_of_4) frames.push_back(st.frames[i]);
        }
    }
    Go1Decoder dec;
    auto out = FeedAll(dec, frames);
    ASSERT_EQ(out.size(), 4u);
    const int64_t start4 = 1'000'000'000 + 8 * testing::kTickNs;
    EXPECT_EQ(dec.Tick(start4 + 6'999'999), 0);
    ASSERT_EQ(dec.Tick(start4 + 7'000'000), 1);  // max_hold_ns
    const Go1Sample s4 = dec.ready()[0];
    EXPECT_EQ(s4.counter, 4);
    EXPECT_FALSE(s4.fresh & kGroupFoot);
    EXPECT_TRUE(s4.valid & kGroupFoot);  // 10 ms old: not timed out yet
    EXPECT_EQ(dec.stats().samples_incomplete, 1u);
    // Its repeats arriving afterwards do not emit it again.
    for (size_t i = 0; i < st.frames.size(); ++i) {
        if (st.sample_of_frame[i] == 4 &&
            st.frames[i].timestamp_ns >= 1'000'000'000 + 9 * testing::kTickNs) {
            EXPECT_EQ(dec.Feed(st.frames[i]).samples, 0);
        }
    }
    // Silence: everything times out, GO1_STATUS (300 ms) last.
    EXPECT_EQ(dec.Tick(start4 + 100'000'000), 0);
    EXPECT_EQ(dec.stats().timeout, 9u);
    EXPECT_EQ(dec.timed_out(), kAllGroups & ~kGroupStatus);
    dec.Tick(start4 + 400'000'000);
    EXPECT_EQ(dec.stats().timeout, 10u);
    EXPECT_EQ(dec.timed_out(), kAllGroups);
    // The bridge comes back with another counter: accepted at once, valid again.
    const Stream again = MakeStream(12, 10, start4 + 1'000'000'000);
    std::vector<CanFrame> shifted = again.frames;
    for (auto& f : shifted) SetCounter(f, static_cast<uint8_t>(((f.data[1] & 0x0F) + 7) % 15));
    out = FeedAll(dec, shifted);
    ASSERT_EQ(out.size(), 12u);
    EXPECT_EQ(out[0].counter, 7);
    EXPECT_EQ(out[0].valid, kAllGroups);
    EXPECT_EQ(dec.stats().counter_resync, 0u);
    EXPECT_EQ(dec.timed_out(), 0);
}

TEST(Go1Decoder, AFrameForAnEmittedSampleIsLate) {
    Stream st = MakeStream(10, 11);
    // BODY_VEL of sample 5 arrives after sample 6 began.
    const size_t from = FrameOf(st, 5, 0x100);
    const CanFrame moved = st.frames[from];
    st.frames.erase(st.frames.begin() + from);
    st.frames.insert(st.frames.begin() + FrameOf(st, 6, 0x0F0) + 1, moved);
    Go1Decoder dec;
    const auto out = FeedAll(dec, st.frames);
    ASSERT_EQ(out.size(), 10u);
    EXPECT_EQ(dec.stats().late, 1u);
    EXPECT_FALSE(out[5].fresh & kGroupBodyVel);
    EXPECT_EQ(dec.stats().counter_lost, 0u);
    for (size_t i = 1; i < out.size(); ++i) EXPECT_NE(out[i].counter, out[i - 1].counter);
}

TEST(Go1Decoder, ConfigIsValidatedAndResetForgetsEverything) {
    Go1DecoderConfig c;
    c.resync_frames = 0;
    EXPECT_THROW(Go1Decoder{c}, common::Error);
    c.resync_frames = 2;
    c.max_hold_ns = -1;
    EXPECT_THROW(c.Validate(), common::Error);
    const Stream st = MakeStream(4, 12);
    Go1Decoder dec;
    const auto first = FeedAll(dec, st.frames);
    dec.Reset();
    EXPECT_EQ(dec.stats().frames, 0u);
    const auto second = FeedAll(dec, st.frames);  // the same counters again: not "late"
    ASSERT_EQ(second.size(), first.size());
    EXPECT_EQ(second.back().vx, first.back().vx);
    std::map<std::string, uint64_t> json;
    dec.stats().ForEach([&](const char* name, uint64_t v) { json[name] = v; });
    EXPECT_EQ(json.size(), 20u);
    EXPECT_EQ(json["frames"], st.frames.size());
    EXPECT_EQ(ToString(Go1Verdict::kCounterResync), "counter_resync");
}

// A long stream with every fault at random: drops, duplicates, reorders, bit flips, foreign and
// malformed frames, silences. Nothing crashes, the counters add up, no sample is emitted twice,
// and whatever is fresh and valid is the truth of its sample.
TEST(Go1Decoder, RandomFaultStreamNeverCrashesAndItsCountersAddUp) {
    const Stream st = MakeStream(6000, 13);  // one minute
    std::mt19937 rng(14);
    std::vector<CanFrame> frames;
    std::uniform_real_distribution<double> p(0, 1);
    int64_t shift = 0;  // silences push the rest of the stream later
    for (size_t i = 0; i < st.frames.size(); ++i) {
        CanFrame f = st.frames[i];
        f.timestamp_ns += shift;
        if (p(rng) < 0.02) continue;                                      // dropped
        if (p(rng) < 0.01) f.data[rng() % 8] ^= uint8_t(1 << rng() % 8);  // the CRC sees it
        if (p(rng) < 0.01 && !frames.empty()) {  // swapped with the previous frame
            std::swap(f, frames.back());
            std::swap(f.timestamp_ns, frames.back().timestamp_ns);
        }
        if (p(rng) < 0.01) frames.push_back(f);  // duplicated
        if (p(rng) < 0.01) {                     // foreign or malformed
            CanFrame g{};
            g.timestamp_ns = f.timestamp_ns;
            g.id = rng() % 2 ? st.frames[rng() % 20].id : rng() % 0x800;
            g.extended = rng() % 8 == 0;
            g.remote = rng() % 16 == 0;
            g.error = rng() % 32 == 0;
            g.fd = rng() % 16 == 0;
            g.len = static_cast<uint8_t>(rng() % 2 ? 8 : rng() % 10);
            for (auto& b : g.data) b = static_cast<uint8_t>(rng());
            frames.push_back(g);
        }
        if (p(rng) < 0.0005) shift += 50'000'000 + rng() % 400'000'000;  // a silence
        frames.push_back(f);
    }
    // Truth by bridge time (microseconds), to identify what an emitted sample is.
    std::map<int64_t, size_t> by_time;
    for (size_t j = 0; j < st.samples.size(); ++j) {
        by_time[st.samples[j].bridge_time_ns / 1000] = j;
    }
    Go1Decoder dec;
    std::vector<Go1Sample> out;
    std::array<uint64_t, 12> verdicts{};
    int64_t next_tick = frames.front().timestamp_ns;
    size_t checked = 0;
    for (const CanFrame& f : frames) {
        while (next_tick <= f.timestamp_ns) {
            dec.Tick(next_tick);
            out.insert(out.end(), dec.ready().begin(), dec.ready().end());
            next_tick += 2'000'000;
        }
        const Go1FeedResult r = dec.Feed(f);
        ++verdicts[static_cast<size_t>(r.verdict)];
        out.insert(out.end(), dec.ready().begin(), dec.ready().end());
    }
    dec.Flush();
    out.insert(out.end(), dec.ready().begin(), dec.ready().end());

    const Go1DecoderStats& s = dec.stats();
    EXPECT_EQ(s.frames, frames.size());
    EXPECT_EQ(SumOfVerdicts(s), s.frames);
    for (size_t v = 0; v < verdicts.size(); ++v) {
        EXPECT_EQ(verdicts[v], s.Count(static_cast<Go1Verdict>(v))) << ToString(Go1Verdict(v));
    }
    EXPECT_EQ(s.samples, out.size());
    EXPECT_GT(s.samples, 5000u);
    for (uint64_t v : {s.foreign_id, s.error_frame, s.bad_frame, s.bad_dlc, s.crc, s.counter_repeat,
                       s.counter_resync, s.resyncing, s.duplicate, s.late, s.counter_lost,
                       s.timeout, s.samples_incomplete}) {
        EXPECT_GT(v, 0u);
    }
    for (size_t i = 0; i < out.size(); ++i) {
        const Go1Sample& o = out[i];
        if (i > 0) {
            // Never twice: a counter comes back only after a full counter cycle.
            EXPECT_TRUE(o.counter != out[i - 1].counter ||
                        o.host_time_ns - out[i - 1].host_time_ns > 70'000'000)
                << i;
            EXPECT_GE(o.host_time_ns, out[i - 1].host_time_ns);
        }
        if (!(o.fresh & kGroupSync)) continue;
        const auto it = by_time.find(o.bridge_time_ns / 1000 % (int64_t{1} << 32));
        ASSERT_NE(it, by_time.end()) << i;
        const size_t j = it->second;
        EXPECT_EQ(o.counter, j % 15) << "output " << i << " host " << o.host_time_ns << " fresh "
                                     << o.fresh << " valid " << o.valid;
        testing::ExpectSameValues(o, st.samples[j], o.fresh & o.valid);
        ++checked;
        if (::testing::Test::HasFailure()) break;
    }
    EXPECT_GT(checked, 4000u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::can
