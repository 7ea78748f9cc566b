#include "host_tools/cli/demo_capture.hpp"

#include <algorithm>
#include <cmath>

#include "algorithms/io/file_util.hpp"
#include "drivers/net/ipv4.hpp"
#include "drivers/net/pcap_writer.hpp"
#include "drivers/ouster/metadata.hpp"
#include "drivers/ouster/packet_encoder.hpp"
#include "host_tools/bim/lidar_from_metadata.hpp"

namespace bimslam::cli {
namespace {

// The simulated image into the frame's fields; fields the profile lacks are simply not encoded.
void FillFrame(const simulation::ScanImage& img, ouster::LidarFrame& frame) {
    std::copy(img.range_mm.begin(), img.range_mm.end(), frame.range.begin());
    if (!frame.reflectivity.empty()) {
        std::copy(img.reflectivity.begin(), img.reflectivity.end(), frame.reflectivity.begin());
    }
    if (!frame.signal.empty()) std::copy(img.signal.begin(), img.signal.end(), frame.signal.begin());
    // Ambient light indoors: a dim, even background.
    if (!frame.near_ir.empty()) std::fill(frame.near_ir.begin(), frame.near_ir.end(), uint16_t(320));
}

}  // namespace

DemoCapture WriteDemoCapture(const simulation::Scene& scene,
                             const std::vector<Eigen::Isometry3d>& poses,
                             const ouster::SensorInfo& info, const std::filesystem::path& dir,
                             const simulation::NoiseModel& noise, uint64_t seed) {
    DemoCapture out;
    out.metadata = dir / "metadata.json";
    out.pcap = dir / "lidar.pcap";
    io::WriteFileAtomic(out.metadata, ouster::SerializeMetadata(info));
    const ouster::PacketEncoder encoder(info);
    const simulation::LidarModel model = bim::LidarModelFromSensorInfo(info);
    net::PcapWriter writer(out.pcap);
    const uint32_t sensor_ip = *net::ParseIpv4("169.254.42.10");
    const uint32_t host_ip = *net::ParseIpv4("169.254.42.1");
    const int w = info.format.columns_per_frame;
    const int64_t frame_ns = static_cast<int64_t>(1e9 / info.frame_rate_hz);
    out.first_frame_ns = 1'000'000'000;  // the sensor's clock starts at boot
    const int64_t host_offset_ns = 1'700'000'000'000'000'000 - out.first_frame_ns;

    // Each frame is cast in parallel over its columns (simulation/lidar_simulator.hpp).
    ouster::LidarFrame f;
    f.Reset(encoder.format());
    simulation::ScanImage image;
    std::vector<uint8_t> packet(encoder.format().lidar_packet_size());
    for (size_t index = 0; index < poses.size(); ++index) {
        simulation::SimulateScan(scene, model, poses[index], noise, seed ^ uint64_t(index), &image);
        FillFrame(image, f);
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
    writer.Close();
    return out;
}

}  // namespace bimslam::cli
