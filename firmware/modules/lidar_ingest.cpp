// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "firmware/modules/lidar_ingest.hpp"

#include <poll.h>

#include <algorithm>
#include <array>
#include <ctime>
#include <optional>
#include <span>
#include <thread>
#include <vector>

#include "algorithms/common/status.hpp"
#include "drivers/net/ipv4.hpp"
#include "drivers/net/packet_recording.hpp"
#include "drivers/net/udp_source.hpp"

namespace bimslam::rig {

int64_t ReplayClock::WaitFor(int64_t capture_ns, const std::atomic<bool>& stop) const {
    if (unpaced()) return runtime::MonotonicNs();
    const int64_t start = start_capture_ns.load(std::memory_order_acquire);
    const int64_t due =
        start_mono_ns + static_cast<int64_t>(double(capture_ns - start) / std::max(speed, 1e-9));
    for (;;) {
        const int64_t now = runtime::MonotonicNs();
        if (now >= due || stop.load(std::memory_order_relaxed)) return now;
        // Sleep in slices of at most 50 ms so that a stop is seen.
        const int64_t wait = std::min<int64_t>(due - now, 50'000'000);
        const timespec t{static_cast<time_t>(wait / 1'000'000'000),
                         static_cast<long>(wait % 1'000'000'000)};
        nanosleep(&t, nullptr);
    }
}

namespace {
constexpr int kAdoptInitIdAfter = 64;  // packets in a row with the same new init_id
constexpr size_t kImuBatch = 16;       // IMU datagrams per read (100 a second)
// A datagram stamped this little before the lidar read may not be in its socket yet (the kernel
// stamps, then queues).
constexpr int64_t kStampToQueueNs = 200'000;
}  // namespace

struct LidarIngest::Impl {
    LidarIngestConfig config;
    ouster::SensorInfo info;
    ouster::FrameBatcher batcher;
    ouster::ImuDecoder imu_decoder;
    runtime::SpscQueue<ScanSlot>& scans;
    runtime::SpscQueue<ImuItem>& imu;
    runtime::SpscQueue<OusterImuItem>& imu_lcm;
    ReplayClock* replay;
    // Live.
    std::optional<net::UdpSource> lidar_socket, imu_socket;
    // IMU datagrams that arrived after this turn's lidar read, routed next turn (LiveTurn).
    struct HeldImu {
        int64_t timestamp_ns = 0;
        std::span<const uint8_t> payload;  // in held_bytes
    };
    std::array<HeldImu, kImuBatch> held;
    size_t held_count = 0;
    std::vector<uint8_t> held_bytes;  // kImuBatch IMU packets, allocated once
    // Replay.
    std::optional<net::PacketRecording> reader;
    int64_t first_capture_ns = kEndOfStream;
    bool have_first = false;
    net::UdpDatagram first;  // read ahead to learn the first capture time

    // imu_sample_t carries the Ouster IMU in its own frame ("imu"); the decoder hands it over in
    // the sensor frame.
    Eigen::Matrix3d R_imu_sensor = Eigen::Matrix3d::Identity();
    IngestCounters c;
    uint64_t imu_pushed = 0;
    uint64_t imu_sequence = 0;
    int64_t last_arrival_ns = 0;        // of any datagram: the arrival clock never goes back
    int64_t last_lidar_arrival_ns = 0;  // of the last lidar packet
    uint32_t candidate_init_id = 0;
    int candidate_count = 0;

    Impl(const LidarIngestConfig& cfg, const ouster::SensorInfo& sensor,
         runtime::SpscQueue<ScanSlot>& s, runtime::SpscQueue<ImuItem>& i,
         runtime::SpscQueue<OusterImuItem>& il, ReplayClock* r)
        : config(cfg),
          info(sensor),
          batcher(sensor),
          imu_decoder(sensor),
          scans(s),
          imu(i),
          imu_lcm(il),
          replay(r) {
        c.init_id = info.init_id;
        R_imu_sensor = info.imu_to_sensor_transform.topLeftCorner<3, 3>().transpose();
    }

    // The slot to fill, waiting for room in a replay; nullptr when the item must be dropped, or
    // in a replay when the run stops (its end, not a drop: NoSlot counts only the former).
    template <typename Q>
    auto Slot(Q& q, const std::atomic<bool>& stop) -> decltype(q.BeginPush()) {
        return q.BeginPushWaiting(replay != nullptr, stop);
    }
    // What a nullptr from Slot means: live, a drop (counted on the queue and in `dropped`); in a
    // replay, the stop.
    template <typename Q>
    void NoSlot(Q& q, uint64_t& dropped) {
        if (replay != nullptr) return;
        q.CountDrop();
        ++dropped;
    }

    // taken_ns: when this thread took up the packet that completed the frames (the latency's
    // breakdown: receive, then decode and assembly).
    void Emit(int64_t arrival_ns, int64_t mono_ns, int64_t taken_ns,
              const std::atomic<bool>& stop) {
        for (const ouster::LidarFrame* frame : batcher.ready()) {
            ScanSlot* slot = Slot(scans, stop);
            if (slot == nullptr) {
                NoSlot(scans, c.scans_dropped);
                continue;
            }
            pipeline::FrameToScan(*frame, arrival_ns, imu_pushed, &slot->scan);
            slot->times.last_packet = mono_ns;
            slot->times.ingested = taken_ns;
            slot->times.queued = runtime::MonotonicNs();
            scans.CommitPush();
            ++c.scans_queued;
        }
    }

    void Lidar(const uint8_t* data, size_t size, int64_t arrival_ns, int64_t mono_ns,
               const std::atomic<bool>& stop) {
        ++c.lidar_datagrams;
        c.bytes += size;
        // A silence: the lidar's own packets stopped (the IMU port may have gone on).
        if (c.last_packet_mono_ns != 0 &&
            arrival_ns - last_lidar_arrival_ns > config.sensor_timeout_ns) {
            ++c.silences;
        }
        last_arrival_ns = last_lidar_arrival_ns = arrival_ns;
        c.last_packet_mono_ns = mono_ns;
        const int64_t taken_ns = runtime::MonotonicNs();
        const ouster::PacketResult r = batcher.AddPacket(data, size, arrival_ns);
        if (r.rejected == ouster::Reject::kInitId) {
            // Adopt a new init_id once it persists: the sensor restarted.
            const uint32_t id = batcher.format().InitId(data);
            candidate_count = id == candidate_init_id ? candidate_count + 1 : 1;
            candidate_init_id = id;
            if (candidate_count >= kAdoptInitIdAfter) {
                batcher.SetExpectedInitId(id);
                imu_decoder.SetExpectedInitId(id);
                c.init_id = id;
                ++c.init_id_changes;
                candidate_count = 0;
            }
        } else if (!r.rejected) {
            candidate_count = 0;
        }
        if (r.frames > 0) Emit(arrival_ns, mono_ns, taken_ns, stop);
    }

    void Imu(const uint8_t* data, size_t size, const std::atomic<bool>& stop) {
        ++c.imu_datagrams;
        c.bytes += size;
        std::array<ouster::ImuSample, 64> samples;
        const auto r = imu_decoder.Decode(data, size, samples);
        for (size_t i = 0; i < r.samples; ++i) {
            ImuItem* slot = Slot(imu, stop);
            if (slot == nullptr) {
                NoSlot(imu, c.imu_dropped);
            } else {
                slot->measurement = pipeline::ImuFromOuster(samples[i]);
                imu.CommitPush();
                ++imu_pushed;
            }
            if (config.publish_imu) {
                ouster::ImuSample in_imu = samples[i];
                in_imu.gyro = R_imu_sensor * samples[i].gyro;
                in_imu.accel = R_imu_sensor * samples[i].accel;
                imu_lcm.PushWaiting({in_imu, imu_sequence}, replay != nullptr, stop);
            }
            ++imu_sequence;
        }
    }

    void Route(uint16_t port, std::span<const uint8_t> payload, int64_t arrival_ns, int64_t mono_ns,
               const std::atomic<bool>& stop) {
        if (arrival_ns < last_arrival_ns) {  // keep the arrival clock monotonic
            ++c.clock_backwards;
            arrival_ns = last_arrival_ns;
        }
        if (port == config.lidar_port) {
            Lidar(payload.data(), payload.size(), arrival_ns, mono_ns, stop);
        } else if (port == config.imu_port) {
            last_arrival_ns = arrival_ns;
            Imu(payload.data(), payload.size(), stop);
        } else {
            ++c.other_datagrams;
        }
    }

    // One live turn: both sockets read, their datagrams routed in the order they arrived. Reading
    // one socket after the other is not enough: an IMU datagram that arrived after the lidar read
    // would be routed before lidar packets that arrived before it and are read only next turn, and
    // the scan they complete would get an IMU sample that came after it. A replay (the recording's
    // order) would not: live and replay must hand the odometry the same samples
    // (algorithms/pipeline/scan_pipeline.hpp, "Order of inputs"). So the lidar socket is read
    // first, and an IMU datagram stamped after that read is held for the next turn. Both sockets
    // are read every turn (non-blocking), not only those poll found readable, for the same reason.
    void LiveTurn(const std::atomic<bool>& stop) {
        const int64_t lidar_read = runtime::RealtimeNs();
        const int64_t rt_minus_mono = lidar_read - runtime::MonotonicNs();
        const net::UdpBatch lidar_batch = lidar_socket->Receive(common::Duration{0});
        const net::UdpBatch imu_batch = imu_socket->Receive(common::Duration{0});
        if (lidar_batch.code == common::StatusCode::kIoError ||
            imu_batch.code == common::StatusCode::kIoError)
            ++c.socket_errors;
        // Everything that arrived before the cutoff has been read: the lidar read's time, or, when
        // its batch was full, its last datagram's.
        int64_t cutoff = lidar_read - kStampToQueueNs;
        if (!lidar_batch.datagrams.empty()) {
            const int64_t last = lidar_batch.datagrams.back().timestamp_ns;
            cutoff = lidar_batch.full ? last : std::max(cutoff, last);
        }
        size_t routable = 0;  // this batch's IMU datagrams up to the cutoff
        while (routable < imu_batch.datagrams.size() &&
               imu_batch.datagrams[routable].timestamp_ns <= cutoff) {
            ++routable;
        }
        // The IMU in arrival order: last turn's held ones, then this batch's routable ones.
        using Stamped = std::pair<int64_t, std::span<const uint8_t>>;
        const size_t imu_n = held_count + routable;
        const auto imu_at = [&](size_t j) {
            if (j < held_count) return Stamped(held[j].timestamp_ns, held[j].payload);
            const net::UdpDatagram& d = imu_batch.datagrams[j - held_count];
            return Stamped(d.timestamp_ns, d.payload);
        };
        const std::span<const net::UdpDatagram> lidar = lidar_batch.datagrams;
        size_t i = 0, j = 0;
        while (i < lidar.size() || j < imu_n) {
            const bool take_lidar =
                j >= imu_n || (i < lidar.size() && lidar[i].timestamp_ns <= imu_at(j).first);
            const Stamped d =
                take_lidar ? Stamped(lidar[i].timestamp_ns, lidar[i].payload) : imu_at(j);
            if (take_lidar) {
                ++i;
            } else {
                ++j;
            }
            const int64_t arrival = d.first - rt_minus_mono;
            Route(take_lidar ? config.lidar_port : config.imu_port, d.second, arrival, arrival,
                  stop);
        }
        held_count = 0;
        const size_t slot = held_bytes.size() / kImuBatch;
        for (size_t k = routable; k < imu_batch.datagrams.size(); ++k) {
            const net::UdpDatagram& d = imu_batch.datagrams[k];
            if (d.payload.size() > slot) {  // not an IMU packet: the decoder counts it, no sample
                Imu(d.payload.data(), d.payload.size(), stop);
                continue;
            }
            uint8_t* to = held_bytes.data() + held_count * slot;
            std::copy(d.payload.begin(), d.payload.end(), to);
            held[held_count++] = {d.timestamp_ns, {to, d.payload.size()}};
        }
    }
};

LidarIngest::LidarIngest(const LidarIngestConfig& config, const ouster::SensorInfo& info,
                         runtime::SpscQueue<ScanSlot>& scans, runtime::SpscQueue<ImuItem>& imu,
                         runtime::SpscQueue<OusterImuItem>& imu_lcm, ReplayClock* replay)
    : impl_(std::make_unique<Impl>(config, info, scans, imu, imu_lcm, replay)) {
    Impl& m = *impl_;
    if (!config.recording.empty()) {
        net::PacketRecordingOptions ro;
        ro.bag_lidar_port = config.lidar_port;
        ro.bag_imu_port = config.imu_port;
        m.reader.emplace(config.recording, ro);
        m.have_first = m.reader->Next(m.first);
        if (m.have_first) m.first_capture_ns = m.first.timestamp_ns;
        description_ = "lidar from " + config.recording.string() + " (lidar port " +
                       std::to_string(config.lidar_port) + ", IMU port " +
                       std::to_string(config.imu_port) + ")";
    } else {
        net::UdpSourceConfig u;
        u.bind_address = config.bind_address;
        u.sensor_address = config.sensor_address;
        u.receive_buffer_bytes = config.receive_buffer_bytes;
        u.port = config.lidar_port;
        m.lidar_socket.emplace(u);
        u.port = config.imu_port;
        u.batch_size = kImuBatch;
        m.held_bytes.resize(kImuBatch * m.imu_decoder.packet_size());
        m.imu_socket.emplace(u);
        description_ = "lidar on UDP " + config.bind_address + ":" +
                       std::to_string(m.lidar_socket->port()) + ", IMU on port " +
                       std::to_string(m.imu_socket->port()) +
                       (config.sensor_address.empty() ? "" : " from " + config.sensor_address);
    }
    counters_.Store(m.c);
}

LidarIngest::~LidarIngest() = default;

int64_t LidarIngest::first_capture_ns() const { return impl_->first_capture_ns; }

std::string LidarIngest::receive_buffer_warning() const {
    return impl_->lidar_socket ? impl_->lidar_socket->receive_buffer_warning() : "";
}

void LidarIngest::Run(runtime::ThreadStats& stats, const std::atomic<bool>& stop) {
    Impl& m = *impl_;
    uint64_t since_publish = 0;
    const auto publish = [&](bool force) {
        if (force || ++since_publish >= 64) {
            m.c.lidar = m.batcher.stats();
            m.c.imu = m.imu_decoder.stats();
            if (m.reader) {
                m.c.ip_bad_checksum = m.reader->extractor_stats().ip_bad_checksum;
            }
            counters_.Store(m.c);
            since_publish = 0;
        }
    };
    if (m.reader) {
        // Replay: the recording's datagrams, paced by their capture times.
        net::UdpDatagram d;
        bool have = m.have_first;
        if (have) d = m.first;
        try {
            while (have && !stop.load(std::memory_order_relaxed)) {
                const int64_t t0 = runtime::MonotonicNs();
                stats.Beat();
                const int64_t mono = m.replay->WaitFor(d.timestamp_ns, stop);
                m.Route(d.dst_port, d.payload, d.timestamp_ns, mono, stop);
                stats.Cycle(runtime::MonotonicNs() - std::max(t0, mono), 0);
                publish(false);
                have = m.reader->Next(d);
            }
        } catch (const common::FileError&) {
            // A corrupt record header ends the recording here: what came before stands.
            ++m.c.socket_errors;
        }
        if (!stop.load()) {
            m.batcher.Flush();
            const int64_t now = runtime::MonotonicNs();
            m.Emit(kEndOfStream, now, now, stop);
        }
        m.c.finished = true;
        publish(true);
        return;
    }
    // Live: both sockets; each turn merges what both hold by receive time (LiveTurn).
    pollfd fds[2] = {{m.lidar_socket->fd(), POLLIN, 0}, {m.imu_socket->fd(), POLLIN, 0}};
    while (!stop.load(std::memory_order_relaxed)) {
        stats.Beat();
        const int ready = ::poll(fds, 2, 100);
        if (ready <= 0) {
            publish(true);
            continue;
        }
        const int64_t t0 = runtime::MonotonicNs();
        m.LiveTurn(stop);
        stats.Cycle(runtime::MonotonicNs() - t0, 0);
        publish(false);
    }
    publish(true);
}

}  // namespace bimslam::rig
