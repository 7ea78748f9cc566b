// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "firmware/modules/can_ingest.hpp"

#include <algorithm>
#include <bimslam/can_frame_t.hpp>
#include <lcm/lcm-cpp.hpp>
#include <optional>
#include <thread>

#include "algorithms/common/status.hpp"
#include "drivers/can/candump.hpp"
#include "drivers/net/can_pcap.hpp"
#include "drivers/net/can_socket.hpp"
#include "drivers/net/pcap_reader.hpp"

namespace bimslam::rig {
namespace {
// STS_BridgeState RUNNING (go1_odometry.dbc VAL_ 320; firmware/go1_bridge BridgeState).
constexpr uint8_t kBridgeRunning = 1;
}  // namespace

struct CanIngest::Impl {
    CanIngestConfig config;
    runtime::SpscQueue<BodyItem>& bodies;
    runtime::SpscQueue<Go1Item>& go1_lcm;
    ReplayClock* replay;
    can::Go1Decoder decoder;
    std::optional<net::CanSocket> socket;
    std::optional<can::CandumpReader> candump;
    std::optional<net::CanPcapReader> pcap;
    std::optional<lcm::LCM> lcm;
    // LCM frames arrive in a callback; they wait here for the thread's turn.
    std::array<common::CanFrame, 256> lcm_frames{};
    size_t lcm_count = 0;
    common::CanFrame first{};
    bool have_first = false;
    CanCounters c;

    Impl(const CanIngestConfig& cfg, runtime::SpscQueue<BodyItem>& b,
         runtime::SpscQueue<Go1Item>& g, ReplayClock* r)
        : config(cfg), bodies(b), go1_lcm(g), replay(r) {}

    bool NextLogFrame(common::CanFrame& frame) {
        if (pcap) return pcap->Next(frame);
        can::CandumpRecord record;
        if (!candump->Next(record)) return false;
        frame = record.frame;
        return true;
    }

    // The bridge's own word on its state, carried by every sample (link) and by STATUS.
    void CountBridge(const can::Go1Sample& s) {
        if (!s.udp_link_ok) ++c.bridge_link_down;
        if (!(s.fresh & can::kGroupStatus)) return;
        c.bridge_state = s.bridge_state;
        if (s.bridge_state != kBridgeRunning) ++c.bridge_not_running;
        c.bridge_lost += s.udp_rx_lost;
    }

    void Take(std::span<const can::Go1Sample> ready, const std::atomic<bool>& stop) {
        for (const can::Go1Sample& s : ready) {
            CountBridge(s);
            BodyItem* slot = bodies.BeginPushWaiting(replay != nullptr, stop);
            if (slot == nullptr) {
                if (replay == nullptr) {  // a replay's nullptr is its stop, not a drop
                    bodies.CountDrop();
                    ++c.bodies_dropped;
                }
            } else {
                slot->body = pipeline::BodyFromGo1(s);
                bodies.CommitPush();
            }
            if (config.publish_go1_state) {
                go1_lcm.PushWaiting({s, decoder.stats(), decoder.timed_out()}, replay != nullptr,
                                    stop);
            }
        }
    }

    // LCM's callback (inside handleTimeout, on this thread): the frame waits for Run's turn.
    void OnLcm(const lcm::ReceiveBuffer*, const std::string&, const bimslam::can_frame_t* msg) {
        if (lcm_count == lcm_frames.size()) {
            ++c.source_errors;
            return;
        }
        common::CanFrame& f = lcm_frames[lcm_count++];
        f = common::CanFrame{};
        f.timestamp_ns = runtime::MonotonicNs();  // the arrival clock
        f.id = uint32_t(msg->id);
        f.extended = msg->flags & bimslam::can_frame_t::FLAG_EFF;
        f.remote = msg->flags & bimslam::can_frame_t::FLAG_RTR;
        f.error = msg->flags & bimslam::can_frame_t::FLAG_ERR;
        f.fd = msg->flags & bimslam::can_frame_t::FLAG_FD;
        f.len = uint8_t(std::clamp<int>(msg->len, 0, 64));
        std::copy(msg->data, msg->data + 64, f.data.begin());
    }

    void Feed(const common::CanFrame& frame, const std::atomic<bool>& stop) {
        ++c.frames;
        c.last_frame_mono_ns = runtime::MonotonicNs();
        if (decoder.Feed(frame).samples > 0) Take(decoder.ready(), stop);
    }
};

CanIngest::CanIngest(const CanIngestConfig& config, runtime::SpscQueue<BodyItem>& bodies,
                     runtime::SpscQueue<Go1Item>& go1_lcm, ReplayClock* replay)
    : impl_(std::make_unique<Impl>(config, bodies, go1_lcm, replay)) {
    Impl& m = *impl_;
    if (config.source == "socketcan") {
        net::CanSocketConfig s;
        s.interface_name = config.interface_name;
        try {
            m.socket.emplace(s);
        } catch (const common::Error& e) {
            throw common::Error(e.code(), std::string(e.what()) +
                                              "; without a CAN bus set can.source to lcm "
                                              "(bimslam-go1-bridge --lcm), log, or none "
                                              "(--handheld)");
        }
        description_ = "Go1 CAN on SocketCAN " + config.interface_name;
    } else if (config.source == "log") {
        if (net::LooksLikePcap(config.log)) {
            m.pcap.emplace(config.log);
        } else {
            can::CandumpReaderConfig cc;
            cc.mode = can::CandumpMode::kLenient;
            m.candump.emplace(config.log, cc);
        }
        m.have_first = m.NextLogFrame(m.first);
        description_ = "Go1 CAN from " + config.log;
    } else if (config.source == "lcm") {
        m.lcm.emplace(config.lcm_url);
        if (!m.lcm->good()) {
            throw common::Error(common::StatusCode::kUnavailable,
                                "LCM " + config.lcm_url +
                                    ": cannot open (no multicast route? "
                                    "toolchain/setup-multicast.sh)");
        }
        m.lcm->subscribe(config.lcm_channel, &Impl::OnLcm, &m);
        description_ = "Go1 CAN from LCM " + config.lcm_channel;
    } else {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "can.source: '" + config.source + "' is not socketcan, lcm or log");
    }
    counters_.Store(m.c);
}

CanIngest::~CanIngest() = default;

int64_t CanIngest::first_capture_ns() const {
    return impl_->have_first ? impl_->first.timestamp_ns : kEndOfStream;
}

void CanIngest::Run(runtime::ThreadStats& stats, const std::atomic<bool>& stop) {
    Impl& m = *impl_;
    int64_t last_store = 0;
    const auto store = [&](bool force) {
        const int64_t now = runtime::MonotonicNs();
        if (force || now - last_store > 20'000'000) {
            m.c.decoder = m.decoder.stats();
            m.c.timed_out = m.decoder.timed_out();
            if (m.socket) m.c.kernel_dropped = m.socket->stats().dropped;
            counters_.Store(m.c);
            last_store = now;
        }
    };
    if (m.candump || m.pcap) {
        common::CanFrame frame = m.first;
        bool have = m.have_first;
        try {
            while (have && !stop.load(std::memory_order_relaxed)) {
                stats.Beat();
                m.replay->WaitFor(frame.timestamp_ns, stop);
                const int64_t t0 = runtime::MonotonicNs();
                if (m.decoder.Tick(frame.timestamp_ns) > 0) m.Take(m.decoder.ready(), stop);
                m.Feed(frame, stop);
                // Every sample received up to this frame has been handed on.
                progress_ns_.store(frame.timestamp_ns, std::memory_order_release);
                stats.Cycle(runtime::MonotonicNs() - t0, 0);
                store(false);
                have = m.NextLogFrame(frame);
            }
        } catch (const common::FileError&) {
            ++m.c.source_errors;  // a corrupt log ends it here
        }
        if (m.decoder.Flush() > 0) m.Take(m.decoder.ready(), stop);
        m.c.finished = true;
        progress_ns_.store(kEndOfStream, std::memory_order_release);
        store(true);
        return;
    }
    while (!stop.load(std::memory_order_relaxed)) {
        stats.Beat();
        const int64_t t0 = runtime::MonotonicNs();
        if (m.socket) {
            const int64_t rt_minus_mono = runtime::RealtimeNs() - t0;
            const net::CanBatch batch = m.socket->Receive(common::Duration::FromMilliseconds(10));
            if (batch.code == common::StatusCode::kIoError) ++m.c.source_errors;
            for (common::CanFrame frame : batch.frames) {
                frame.timestamp_ns -= rt_minus_mono;  // to the arrival clock (monotonic)
                m.Feed(frame, stop);
            }
        } else {
            m.lcm->handleTimeout(10);
            for (size_t i = 0; i < m.lcm_count; ++i) m.Feed(m.lcm_frames[i], stop);
            m.lcm_count = 0;
        }
        const int64_t now = runtime::MonotonicNs();
        if (m.decoder.Tick(now) > 0) m.Take(m.decoder.ready(), stop);
        progress_ns_.store(now, std::memory_order_release);
        stats.Cycle(now - t0, 0);
        store(false);
    }
    store(true);
}

}  // namespace bimslam::rig
