// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Lidar packets to frames (specs/ouster-lidar.md, "Batching columns into frames"):
// - a packet with a newer frame id (16-bit wrap-aware, 32-bit for FUSA) closes the frame being
//   filled; packets of an older frame arriving late are dropped and counted; reordering within a
//   frame is harmless because columns are placed by measurement id;
// - a frame is emitted as soon as every column of the column window arrived, without waiting for
//   the next frame; a closed frame missing columns is emitted with them zeroed and invalid;
// - every packet is validated (size, packet type, prod_sn, init_id, CRC footer, measurement ids)
//   and every rejection is counted by cause;
// - an init_id change (sensor restart) closes the frame and resets.
// No allocation after the first frame, no exceptions, no locks: this runs per packet on the rig.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "drivers/ouster/lidar_frame.hpp"
#include "drivers/ouster/packet_format.hpp"
#include "drivers/ouster/sensor_info.hpp"
#include "drivers/ouster/xyz_lut.hpp"

namespace bimslam::ouster {

enum class Reject : uint8_t {
    kSize,           // not the lidar packet size of the metadata's profile and H
    kPacketType,     // header packet_type is not 1 (lidar)
    kProdSn,         // header prod_sn differs from the metadata's
    kInitId,         // header init_id differs from the metadata's
    kCrc,            // CRC-64 footer set and wrong
    kMeasurementId,  // a column's measurement id >= columns_per_frame
    kLate,           // belongs to a frame already emitted or superseded
    kDuplicate,      // its columns were already received for this frame
};
inline constexpr int kNumRejects = 8;
std::string_view ToString(Reject r);  // "size", "packet_type", ... (JSON keys)

struct LidarStats {
    uint64_t packets = 0;  // offered to AddPacket
    uint64_t accepted = 0;
    std::array<uint64_t, kNumRejects> rejected{};
    uint64_t crc_checked = 0;
    uint64_t frames_complete = 0;
    uint64_t frames_incomplete = 0;
    uint64_t columns_lost = 0;     // window columns missing from emitted frames
    uint64_t sensor_restarts = 0;  // init_id changes (metadata without init_id)

    uint64_t Rejected(Reject r) const { return rejected[static_cast<size_t>(r)]; }
    uint64_t TotalRejected() const;
};

struct BatcherConfig {
    bool check_crc = true;    // verify non-zero CRC-64 footers
    bool compute_xyz = true;  // fill LidarFrame::xyz on emission
};

struct PacketResult {
    int frames = 0;                  // frames emitted by this call (0, 1 or 2), see ready()
    std::optional<Reject> rejected;  // why the packet was dropped, if it was
};

class FrameBatcher {
public:
    // Throws common::Error when the metadata describes no valid packet layout.
    explicit FrameBatcher(const SensorInfo& info, BatcherConfig config = {});

    PacketResult AddPacket(const uint8_t* data, size_t size, int64_t arrival_ns = 0);
    // End of stream: emits the frame being filled, if it holds any column.
    int Flush();
    // Forgets every frame and counter, as after construction, without allocating.
    void Reset();
    // The init_id packets are checked against from now on: a sensor that restarted sends a new
    // one, which its user accepts once it has seen it persist (the batcher alone cannot tell a
    // restart from another sensor on the port). Frames emit as after any init_id change.
    void SetExpectedInitId(uint32_t init_id) { info_.init_id = init_id; }
    // The frames emitted by the last AddPacket or Flush, oldest first; valid until the next call.
    std::span<const LidarFrame* const> ready() const { return {ready_.data(), ready_count_}; }

    const LidarStats& stats() const { return stats_; }
    const PacketFormat& format() const { return format_; }
    const SensorInfo& info() const { return info_; }

private:
    bool Newer(uint32_t a, uint32_t b) const;  // a after b, wrap-aware
    void StartFrame(uint32_t frame_id, uint32_t init_id);
    void Emit();
    void Decode(const uint8_t* p, int64_t arrival_ns);
    PacketResult Drop(ouster::Reject r);

    SensorInfo info_;
    PacketFormat format_;
    BatcherConfig config_;
    XyzLut<float> lut_;
    std::array<LidarFrame, 3> pool_;  // the frame being filled + up to two emitted
    std::array<const LidarFrame*, 2> ready_{};
    size_t ready_count_ = 0;
    size_t current_ = 0;                     // pool index of the frame being filled
    bool filling_ = false;                   // current_ holds at least one packet
    std::optional<uint32_t> last_frame_id_;  // the most recent frame started
    std::optional<uint32_t> last_init_id_;
    std::vector<uint8_t> received_;  // per column of the frame being filled
    LidarStats stats_;
};

}  // namespace bimslam::ouster
