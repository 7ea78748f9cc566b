// The demo's capture: a walk through the sample building written as a real Ouster recording, a
// pcap of UDP packets fragmented at MTU 1500 plus its metadata JSON, so that the rest of the demo
// reads it with the same driver a real recording goes through. Each frame is ray-cast by
// algorithms/simulation along the sensor's own XYZ table, so decoding gives back the cast points
// (up to range quantisation and noise). A stand-in until the capture simulator exists: the sensor
// does not move during a rotation and there is no IMU or Go1 data.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "algorithms/simulation/lidar_simulator.hpp"
#include "algorithms/simulation/scene.hpp"
#include "drivers/ouster/sensor_info.hpp"

namespace bimslam::cli {

struct DemoCapture {
    std::filesystem::path pcap;
    std::filesystem::path metadata;
    int64_t first_frame_ns = 0;  // sensor clock of frame 0's first column
    size_t packets = 0;
    size_t bytes = 0;
};

// One frame per pose (T_world_sensor), at the sensor's frame rate; noise.range_resolution_mm
// should match the profile's (8 mm for RNG15).
DemoCapture WriteDemoCapture(const simulation::Scene& scene,
                             const std::vector<Eigen::Isometry3d>& poses,
                             const ouster::SensorInfo& info, const std::filesystem::path& dir,
                             const simulation::NoiseModel& noise, uint64_t seed);

}  // namespace bimslam::cli
