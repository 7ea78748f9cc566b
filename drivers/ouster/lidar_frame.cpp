// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/ouster/lidar_frame.hpp"

#include <algorithm>

namespace bimslam::ouster {
namespace {
template <typename T>
void Size(std::vector<T>& v, size_t n, bool present) {
    if (!present) {
        v.clear();
        return;
    }
    if (v.size() != n)
        v.assign(n, T{});  // allocates only when the shape changes
    else
        std::fill(v.begin(), v.end(), T{});
}
}  // namespace

void LidarFrame::Reset(const PacketFormat& f) {
    h = f.pixels_per_column();
    w = f.columns_per_frame();
    profile = f.profile();
    complete = false;
    columns_received = 0;
    packets = 0;
    start_ns = 0;
    first_arrival_ns = last_arrival_ns = 0;
    frame_id = init_id = 0;
    const size_t n = static_cast<size_t>(h) * w;
    const size_t cols = static_cast<size_t>(w);
    Size(timestamp, cols, true);
    Size(measurement_id, cols, true);
    Size(status, cols, true);
    Size(encoder, cols, f.legacy());
    Size(column_frame_id, cols, f.legacy());
    for (int k = 0; k < kNumFields; ++k) {
        const auto field = static_cast<Field>(k);
        VisitField(field, [&](auto& image) { Size(image, n, f.Has(field)); });
    }
    if (xyz.size() != n) xyz.assign(n, Eigen::Vector3f::Zero());
}

void LidarFrame::ZeroColumn(int v) {
    timestamp[v] = 0;
    measurement_id[v] = 0;
    status[v] = 0;
    if (!encoder.empty()) encoder[v] = 0;
    if (!column_frame_id.empty()) column_frame_id[v] = 0;
    for (int k = 0; k < kNumFields; ++k) {
        VisitField(static_cast<Field>(k), [this, v](auto& image) {
            if (image.empty()) return;
            for (int u = 0; u < h; ++u) image[Index(u, v)] = 0;
        });
    }
}

const void* LidarFrame::FieldData(Field f) const {
    return VisitField(
        f, [](const auto& image) -> const void* { return image.empty() ? nullptr : image.data(); });
}

void ToPointCloud(const LidarFrame& frame, common::PointCloud* out) {
    out->Clear();
    out->stamp = common::SensorTime{static_cast<int64_t>(frame.start_ns)};
    out->frame = "os_sensor";
    if (frame.range.empty()) return;
    const bool use_reflectivity = !frame.reflectivity.empty();
    // Sized for every pixel and written in place, then cut to the points kept: appending a point
    // at a time cost a call and four capacity checks a point, and the rig does this between a
    // frame's last packet and its odometry. Within a reserved cloud nothing is allocated.
    const size_t pixels = static_cast<size_t>(frame.h) * static_cast<size_t>(frame.w);
    out->xyz.resize(pixels);
    out->intensity.resize(pixels);
    out->ring.resize(pixels);
    out->time_offset_ns.resize(pixels);
    Eigen::Vector3f* xyz = out->xyz.data();
    float* intensity = out->intensity.data();
    uint16_t* ring = out->ring.data();
    uint32_t* time = out->time_offset_ns.data();
    size_t k = 0;
    for (int v = 0; v < frame.w; ++v) {
        if (!frame.ColumnValid(v)) continue;
        const auto dt = static_cast<uint32_t>(frame.timestamp[v] - frame.start_ns);
        for (int u = 0; u < frame.h; ++u) {
            const size_t i = frame.Index(u, v);
            if (frame.range[i] == 0) continue;
            xyz[k] = frame.xyz[i];
            intensity[k] =
                use_reflectivity ? frame.reflectivity[i] : static_cast<float>(frame.signal[i]);
            ring[k] = static_cast<uint16_t>(u);
            time[k] = dt;
            ++k;
        }
    }
    out->xyz.resize(k);
    out->intensity.resize(k);
    out->ring.resize(k);
    out->time_offset_ns.resize(k);
}

}  // namespace bimslam::ouster
