#include "host_tools/cli/demo_capture.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <thread>

#include "algorithms/io/file_util.hpp"
#include "drivers/net/ipv4.hpp"
#include "drivers/net/pcap_writer.hpp"
#include "drivers/ouster/metadata.hpp"
#include "drivers/ouster/packet_encoder.hpp"
#include "drivers/ouster/xyz_lut.hpp"

namespace bimslam::cli {
namespace {

// Fills the frame's fields for a sensor at T_world_sensor.
void CastFrame(const DemoScene& scene, const ouster::XyzLut<double>& lut,
               const Eigen::Isometry3d& T_world_sensor, double sigma_m, uint32_t seed,
               ouster::LidarFrame& frame) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, sigma_m);
    for (int u = 0; u < frame.h; ++u) {
        for (int v = 0; v < frame.w; ++v) {
            // The LUT's point for range r is offset + r * direction: the ray starts at the
            // offset and r is measured along the direction.
            const Eigen::Vector3d origin = T_world_sensor * lut.offset(u, v);
            const Eigen::Vector3d dir = T_world_sensor.linear() * lut.direction(u, v);
            double cos_incidence = 0;
            const double r = scene.Cast(origin, dir, &cos_incidence) + noise(rng);
            const size_t i = frame.Index(u, v);
            const bool hit = std::isfinite(r) && r > 0.3 && r < 120.0;
            frame.range[i] = hit ? static_cast<uint32_t>(std::lround(r * 1000.0)) : 0;
            // Painted walls reflect ~40 %; the return weakens with incidence and range. Fields
            // the profile lacks are simply not encoded.
            if (!frame.reflectivity.empty()) {
                frame.reflectivity[i] = hit ? static_cast<uint8_t>(20 + 40 * cos_incidence) : 0;
            }
            if (!frame.signal.empty()) {
                frame.signal[i] =
                    hit ? static_cast<uint16_t>(4000 * cos_incidence / (1 + r * r / 25)) : 0;
            }
            if (!frame.near_ir.empty())
                frame.near_ir[i] = static_cast<uint16_t>(16 * (20 + rng() % 4));
        }
    }
}

}  // namespace

DemoCapture WriteDemoCapture(const DemoScene& scene, const std::vector<Eigen::Isometry3d>& poses,
                             const ouster::SensorInfo& info, const std::filesystem::path& dir,
                             double sigma_m, uint32_t seed) {
    DemoCapture out;
    out.metadata = dir / "metadata.json";
    out.pcap = dir / "lidar.pcap";
    io::WriteFileAtomic(out.metadata, ouster::SerializeMetadata(info));
    const ouster::PacketEncoder encoder(info);
    const ouster::XyzLut<double> lut(info);
    net::PcapWriter writer(out.pcap);
    const uint32_t sensor_ip = *net::ParseIpv4("169.254.42.10");
    const uint32_t host_ip = *net::ParseIpv4("169.254.42.1");
    const int w = info.format.columns_per_frame;
    const int64_t frame_ns = static_cast<int64_t>(1e9 / info.frame_rate_hz);
    out.first_frame_ns = 1'000'000'000;  // the sensor's clock starts at boot
    const int64_t host_offset_ns = 1'700'000'000'000'000'000 - out.first_frame_ns;

    // Frames are cast in parallel in small batches and written in order.
    const unsigned workers = std::max(1u, std::thread::hardware_concurrency());
    std::vector<ouster::LidarFrame> batch(workers * 2);
    for (auto& f : batch) f.Reset(encoder.format());
    std::vector<uint8_t> packet(encoder.format().lidar_packet_size());
    for (size_t first = 0; first < poses.size(); first += batch.size()) {
        const size_t n = std::min(batch.size(), poses.size() - first);
        std::vector<std::thread> threads;
        for (unsigned t = 0; t < workers; ++t) {
            threads.emplace_back([&, t] {
                for (size_t k = t; k < n; k += workers) {
                    CastFrame(scene, lut, poses[first + k], sigma_m,
                              seed + static_cast<uint32_t>(first + k), batch[k]);
                }
            });
        }
        for (auto& th : threads) th.join();
        for (size_t k = 0; k < n; ++k) {
            ouster::LidarFrame& f = batch[k];
            const size_t index = first + k;
            f.frame_id = static_cast<uint32_t>(index & 0xFFFF);
            const int64_t start = out.first_frame_ns + static_cast<int64_t>(index) * frame_ns;
            for (int v = 0; v < w; ++v) {
                f.timestamp[v] = static_cast<uint64_t>(start + frame_ns * v / w);
                f.measurement_id[v] = static_cast<uint16_t>(v);
                f.status[v] = 1;
            }
            for (int p = 0; p < encoder.packets_per_frame(); ++p) {
                encoder.EncodeLidarPacket(f, p, packet.data());
                // Sent when its last column is measured.
                const int64_t sent = static_cast<int64_t>(
                    f.timestamp[(p + 1) * encoder.format().columns_per_packet() - 1]);
                writer.WriteUdp(sent + host_offset_ns, sensor_ip, 7502, host_ip, 7502, packet,
                                1500);
                ++out.packets;
                out.bytes += packet.size();
            }
        }
    }
    writer.Close();
    return out;
}

}  // namespace bimslam::cli
