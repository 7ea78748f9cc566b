// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Where the files of a recording are. A recording is given as either
// - a capture folder, as the rig records and `bimslam simulate` writes it: lidar.pcap,
//   metadata.json, go1_can.log when the Go1 was there, capture.json (the mount) when known; or
// - a pcap with its metadata JSON the way Ouster's own tools save them: x.pcap and x.json beside
//   it (else metadata.json in the same folder). No CAN log and no mount then, unless given; or
// - a ROS 1 bag as ouster-ros records it (x.bag): packets and metadata in one file, read by
//   drivers/net's RosPacketBag (the metadata from the bag's metadata topic).
// Only paths are resolved here (no reading), so every tool that takes a recording accepts the
// same three forms with the same messages.
#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <optional>
#include <string>

namespace bimslam::io {

struct CaptureFiles {
    std::filesystem::path packets;  // lidar + IMU packets: a pcap, or the bag
    std::filesystem::path
        metadata;  // the sensor's metadata JSON; a bag: empty (inside), unless given
    std::filesystem::path can_log;       // empty when the recording has none
    std::filesystem::path capture_json;  // empty when absent
    bool folder = false;                 // given as a capture folder
    bool bag = false;                    // given as a ROS bag (.bag)
};

// Throws common::FileError (kNotFound) naming the path and what was looked for. `metadata`, when
// given, is the sensor's metadata JSON instead of the one found beside (or inside) the recording.
CaptureFiles ResolveCapture(const std::filesystem::path& recording,
                            const std::filesystem::path& metadata = {});

// The lidar's mount T_base_sensor recorded in a capture.json, if the file and key exist. Throws
// common::FileError when the file exists but the key is malformed.
std::optional<Eigen::Isometry3d> ReadCaptureMount(const std::filesystem::path& capture_json);

}  // namespace bimslam::io
