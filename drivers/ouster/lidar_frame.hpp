// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// One rotation of an Ouster sensor: staggered field images, per-column headers, XYZ, and what
// went missing (specs/ouster-lidar.md, "Batching columns into frames"). Filled by FrameBatcher;
// buffers are sized once and reused, so the hot path never allocates after the first frame.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "algorithms/common/point_cloud.hpp"
#include "drivers/ouster/packet_format.hpp"

namespace bimslam::ouster {

struct LidarFrame {
    int h = 0;              // pixels per column (rows)
    int w = 0;              // columns per frame
    uint32_t frame_id = 0;  // 16-bit, 32-bit for FUSA headers
    uint32_t init_id = 0;   // 0 for LEGACY
    LidarProfile profile = LidarProfile::kLegacy;
    bool complete = false;         // every column of the window arrived
    int columns_received = 0;      // within the window
    int columns_expected = 0;      // the window's size
    int packets = 0;               // accepted packets of this frame
    uint64_t start_ns = 0;         // sensor clock: earliest valid column timestamp
    int64_t first_arrival_ns = 0;  // host clock of the first and last packet (0 when unknown)
    int64_t last_arrival_ns = 0;

    // Per column v (index = measurement_id). Missing and out-of-window columns are zero.
    std::vector<uint64_t> timestamp;
    std::vector<uint16_t> measurement_id;
    std::vector<uint32_t> status;           // bit 0 = valid
    std::vector<uint32_t> encoder;          // LEGACY only
    std::vector<uint16_t> column_frame_id;  // LEGACY only

    // Staggered H x W images, row-major (row u, column v), empty when the profile lacks the field.
    std::vector<uint32_t> range, range2;  // millimetres
    std::vector<uint16_t> signal, signal2, near_ir;
    std::vector<uint8_t> reflectivity, reflectivity2, flags, flags2;

    // XYZ of the first return in the sensor frame, metres, H x W row-major; zero where range is 0.
    std::vector<Eigen::Vector3f> xyz;

    // Sizes every buffer for the format (allocates only when the shape changes) and zeroes it.
    void Reset(const PacketFormat& format);
    // Zeroes column v: its header entries and its pixels in every image (a missing column).
    void ZeroColumn(int v);
    bool ColumnValid(int v) const { return (status[v] & 1u) != 0; }
    size_t Index(int u, int v) const { return static_cast<size_t>(u) * w + v; }

    // The image of a field as raw bytes (for export and digests); nullptr when absent.
    const void* FieldData(Field f) const;

    // Calls fn(image) with the std::vector of field f: the one place that maps a Field to its
    // member, so decoding, encoding, zeroing and export cannot disagree.
    template <typename Fn>
    decltype(auto) VisitField(Field f, Fn&& fn) {
        switch (f) {
            case Field::kRange:
                return fn(range);
            case Field::kRange2:
                return fn(range2);
            case Field::kSignal:
                return fn(signal);
            case Field::kSignal2:
                return fn(signal2);
            case Field::kReflectivity:
                return fn(reflectivity);
            case Field::kReflectivity2:
                return fn(reflectivity2);
            case Field::kNearIr:
                return fn(near_ir);
            case Field::kFlags:
                return fn(flags);
            case Field::kFlags2:
                return fn(flags2);
        }
        return fn(flags2);  // not reached: every Field is a case above
    }
    template <typename Fn>
    decltype(auto) VisitField(Field f, Fn&& fn) const {
        return const_cast<LidarFrame*>(this)->VisitField(
            f, [&fn](const auto& image) -> decltype(auto) { return fn(image); });
    }
};

// Points with a non-zero range, column by column (in time order): xyz, intensity (reflectivity,
// else signal), ring = row u (the driver's beam index; never guessed from elevation), and the
// offset of the column's timestamp from start_ns. `out` keeps its capacity between calls.
void ToPointCloud(const LidarFrame& frame, common::PointCloud* out);

// Destaggering of an H x W image (specs/ouster-lidar.md):
// out[u][(v + pixel_shift_by_row[u]) mod W] = in[u][v].
template <typename T>
void Destagger(const T* in, int h, int w, const std::vector<int>& pixel_shift_by_row, T* out) {
    for (int u = 0; u < h; ++u) {
        const int shift = ((pixel_shift_by_row[u] % w) + w) % w;
        const T* src = in + static_cast<size_t>(u) * w;
        T* dst = out + static_cast<size_t>(u) * w;
        for (int v = 0; v < w; ++v) {
            const int d = v + shift;
            dst[d >= w ? d - w : d] = src[v];
        }
    }
}

}  // namespace bimslam::ouster
