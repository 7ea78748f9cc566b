// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/ouster/frame_batcher.hpp"

#include <algorithm>

#include "drivers/ouster/crc64.hpp"

namespace bimslam::ouster {
namespace {

// One field of one packet into its image: a pass per field keeps the inner loop free of type
// dispatch, and the packet (a few KB) stays in L1 across the passes. Rows outside, columns
// inside: the 16 columns of a packet are adjacent in a row, so each row gets one contiguous
// write. Columns outside would write H rows W elements apart, a power-of-two stride that maps
// every row to the same cache set and thrashes L1 (measured: 2.4x slower per frame).
template <typename T>
void ExtractField(const PacketFormat& f, const FieldSpec& spec, const uint8_t* p,
                  const uint16_t* columns, const bool* valid, int n, T* image) {
    const int h = f.pixels_per_column(), w = f.columns_per_frame();
    const size_t px = f.pixel_size();
    const uint8_t* first = f.Pixels(f.Column(p, 0)) + 4 * spec.word;
    const size_t column_stride = static_cast<size_t>(f.Column(p, 1) - f.Column(p, 0));
    // Locals, so that stores into the image cannot be taken for writes to the spec.
    const uint32_t shift = spec.shift, mask = spec.mask, multiplier = spec.multiplier;
    // The usual packet: every column valid, measurement ids consecutive. Then each row is one
    // straight loop the compiler unrolls.
    bool contiguous = true;
    for (int c = 0; c < n; ++c) contiguous = contiguous && valid[c] && columns[c] == columns[0] + c;
    for (int u = 0; u < h; ++u) {
        T* __restrict row = image + static_cast<size_t>(u) * w;
        const uint8_t* pix = first + u * px;
        if (contiguous) {
            T* __restrict out = row + columns[0];
            for (int c = 0; c < n; ++c) {
                out[c] = static_cast<T>(((Load32(pix + c * column_stride) >> shift) & mask) *
                                        multiplier);
            }
            continue;
        }
        for (int c = 0; c < n; ++c) {
            if (!valid[c]) continue;
            row[columns[c]] =
                static_cast<T>(((Load32(pix + c * column_stride) >> shift) & mask) * multiplier);
        }
    }
}

}  // namespace

std::string_view ToString(Reject r) {
    switch (r) {
        case Reject::kSize:
            return "size";
        case Reject::kPacketType:
            return "packet_type";
        case Reject::kProdSn:
            return "prod_sn";
        case Reject::kInitId:
            return "init_id";
        case Reject::kCrc:
            return "crc";
        case Reject::kMeasurementId:
            return "measurement_id";
        case Reject::kLate:
            return "late";
        case Reject::kDuplicate:
            return "duplicate";
    }
    return "?";
}

uint64_t LidarStats::TotalRejected() const {
    uint64_t n = 0;
    for (uint64_t r : rejected) n += r;
    return n;
}

FrameBatcher::FrameBatcher(const SensorInfo& info, BatcherConfig config)
    : info_(info), format_(info), config_(config), lut_(info) {
    for (auto& f : pool_) f.Reset(format_);  // all allocation happens here
    received_.assign(static_cast<size_t>(format_.columns_per_frame()), 0);
}

bool FrameBatcher::Newer(uint32_t a, uint32_t b) const {
    if (format_.header_type() == HeaderType::kFusa && !format_.legacy()) {
        return static_cast<int32_t>(a - b) > 0;
    }
    return static_cast<int16_t>(static_cast<uint16_t>(a - b)) > 0;
}

PacketResult FrameBatcher::Drop(ouster::Reject r) {
    ++stats_.rejected[static_cast<size_t>(r)];
    PacketResult out;
    out.frames = static_cast<int>(ready_count_);
    out.rejected = r;
    return out;
}

PacketResult FrameBatcher::AddPacket(const uint8_t* p, size_t size, int64_t arrival_ns) {
    ready_count_ = 0;
    ++stats_.packets;
    const PacketFormat& f = format_;
    if (size != f.lidar_packet_size()) return Drop(Reject::kSize);
    if (!f.legacy()) {
        if (f.PacketType(p) != 1) return Drop(Reject::kPacketType);
        if (info_.prod_sn != 0 && f.ProdSn(p) != info_.prod_sn) return Drop(Reject::kProdSn);
        if (info_.init_id != 0 && f.InitId(p) != info_.init_id) return Drop(Reject::kInitId);
        if (config_.check_crc && f.HasCrcFooter() && f.FooterCrc(p) != 0) {
            ++stats_.crc_checked;
            if (Crc64Xz(p, size - 8) != f.FooterCrc(p)) return Drop(Reject::kCrc);
        }
    }
    for (int c = 0; c < f.columns_per_packet(); ++c) {
        if (f.MeasurementId(f.Column(p, c)) >= f.columns_per_frame()) {
            return Drop(Reject::kMeasurementId);
        }
    }
    const uint32_t frame_id = f.FrameId(p);
    const uint32_t init_id = f.InitId(p);
    if (!f.legacy() && last_init_id_ && init_id != *last_init_id_) {
        // The sensor re-initialised: what was being batched belongs to another session.
        ++stats_.sensor_restarts;
        if (filling_) Emit();
        last_frame_id_.reset();
    }
    last_init_id_ = init_id;
    if (last_frame_id_ && frame_id != *last_frame_id_ && !Newer(frame_id, *last_frame_id_)) {
        return Drop(Reject::kLate);
    }
    if (last_frame_id_ && frame_id == *last_frame_id_ && !filling_) {
        return Drop(Reject::kLate);  // its frame was already emitted complete
    }
    if (!last_frame_id_ || frame_id != *last_frame_id_) {
        if (filling_) Emit();  // closed by a newer frame: emitted incomplete
        StartFrame(frame_id, init_id);
    }
    if (received_[f.MeasurementId(f.Column(p, 0))]) return Drop(Reject::kDuplicate);
    Decode(p, arrival_ns);
    ++stats_.accepted;
    LidarFrame& frame = pool_[current_];
    if (frame.columns_received >= frame.columns_expected) Emit();
    return {static_cast<int>(ready_count_), std::nullopt};
}

void FrameBatcher::StartFrame(uint32_t frame_id, uint32_t init_id) {
    // Take a pool buffer that is not among the frames just emitted.
    for (size_t i = 0; i < pool_.size(); ++i) {
        const LidarFrame* candidate = &pool_[i];
        if (std::find(ready_.begin(), ready_.begin() + ready_count_, candidate) ==
            ready_.begin() + ready_count_) {
            current_ = i;
            break;
        }
    }
    // No zeroing here: every column that arrives is overwritten, and Emit zeroes the ones that
    // did not, so a complete frame costs no extra pass over its buffers.
    LidarFrame& frame = pool_[current_];
    frame.frame_id = frame_id;
    frame.init_id = init_id;
    frame.complete = false;
    frame.columns_received = 0;
    frame.packets = 0;
    frame.start_ns = 0;
    frame.first_arrival_ns = frame.last_arrival_ns = 0;
    frame.columns_expected = info_.format.WindowColumns();
    std::fill(received_.begin(), received_.end(), uint8_t{0});
    last_frame_id_ = frame_id;
    filling_ = true;
}

void FrameBatcher::Decode(const uint8_t* p, int64_t arrival_ns) {
    const PacketFormat& f = format_;
    LidarFrame& frame = pool_[current_];
    uint16_t columns[64];
    bool valid[64];
    const int n = std::min(f.columns_per_packet(), 64);
    for (int c = 0; c < n; ++c) {
        const uint8_t* col = f.Column(p, c);
        const uint16_t m = f.MeasurementId(col);
        columns[c] = m;
        const uint32_t status = f.ColumnStatus(col);
        // Columns outside the window (or flagged invalid) keep zeroed data (spec).
        valid[c] = (status & 1u) != 0 && info_.format.InWindow(m) && !received_[m];
        frame.timestamp[m] = f.ColumnTimestamp(col);
        frame.measurement_id[m] = m;
        frame.status[m] = status;
        if (f.legacy()) {
            frame.encoder[m] = f.EncoderCount(col);
            frame.column_frame_id[m] = f.ColumnFrameId(col);
        }
        if (valid[c]) {
            received_[m] = 1;
            ++frame.columns_received;
            const uint64_t t = frame.timestamp[m];
            if (frame.start_ns == 0 || t < frame.start_ns) frame.start_ns = t;
        }
    }
    for (const FieldSpec& spec : f.fields()) {
        frame.VisitField(spec.field, [&](auto& image) {
            ExtractField(f, spec, p, columns, valid, n, image.data());
        });
    }
    ++frame.packets;
    if (frame.first_arrival_ns == 0) frame.first_arrival_ns = arrival_ns;
    frame.last_arrival_ns = arrival_ns;
}

void FrameBatcher::Emit() {
    LidarFrame& frame = pool_[current_];
    frame.complete = frame.columns_received >= frame.columns_expected;
    if (frame.columns_received < frame.w) {
        for (int v = 0; v < frame.w; ++v) {
            if (!received_[v]) frame.ZeroColumn(v);  // lost, invalid or outside the window
        }
    }
    if (frame.complete) {
        ++stats_.frames_complete;
    } else {
        ++stats_.frames_incomplete;
        stats_.columns_lost +=
            static_cast<uint64_t>(frame.columns_expected - frame.columns_received);
    }
    if (config_.compute_xyz) lut_.Compute(frame.range.data(), frame.xyz.data());
    ready_[ready_count_++] = &frame;
    filling_ = false;
}

void FrameBatcher::Reset() {
    ready_count_ = 0;
    current_ = 0;
    filling_ = false;
    last_frame_id_.reset();
    last_init_id_.reset();
    std::fill(received_.begin(), received_.end(), uint8_t{0});
    stats_ = LidarStats{};
}

int FrameBatcher::Flush() {
    ready_count_ = 0;
    if (filling_) Emit();
    return static_cast<int>(ready_count_);
}

}  // namespace bimslam::ouster
