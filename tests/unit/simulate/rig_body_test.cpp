// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The platform's own body in a capture (sensor.body_in_view): it shows where rig_body.hpp puts it
// in the sensor frame, in every frame while the platform moves, and changes nothing else but what
// it hides.
#include "host_tools/simulate/rig_body.hpp"

#include <gtest/gtest.h>

#include "drivers/ouster/metadata.hpp"
#include "host_tools/capture/ouster_capture.hpp"
#include "host_tools/simulate/simulate.hpp"
#include "tests/support/test_support.hpp"
#include "tests/unit/bim/synthetic_floor.hpp"

namespace bimslam::simulate {
namespace {
namespace BIMSLAM_UNITY_ID {

std::vector<ouster::LidarFrame> Frames(const std::filesystem::path& dir) {
    const ouster::SensorInfo info = ouster::LoadMetadata(dir / "metadata.json");
    capture::OusterCapture capture(dir / "lidar.pcap", info);
    std::vector<ouster::LidarFrame> frames;
    while (const ouster::LidarFrame* f = capture.NextFrame()) frames.push_back(*f);
    return frames;
}

class RigBodyInView : public ::testing::TestWithParam<Platform> {};

TEST_P(RigBodyInView, ShowsWhereItIsInTheSensorFrameAndOnlyThere) {
    Scenario s = DefaultScenario(GetParam());
    s.duration_s = 1.5;
    s.sensor.model = "OS0-32";  // 90 deg of view: the Go1's trunk is in it
    const bim::BimModel model = bim::test_floor::Floor();
    test::TempDir dir;
    SimulateCapture(s, model, "none", dir / "without");
    s.sensor.body_in_view = true;
    SimulateCapture(s, model, "none", dir / "with");
    const auto without = Frames(dir / "without"), with = Frames(dir / "with");
    ASSERT_EQ(with.size(), without.size());
    ASSERT_GE(with.size(), 10u);

    // The body's bounding box in the sensor frame (the default mounts have no rotation), with
    // room for 1 cm range noise and the quantisation.
    Eigen::AlignedBox3f body;
    for (const Eigen::Vector3f& v : RigBody(s.platform).vertices) {
        body.extend(v - s.sensor.mount_xyz.cast<float>());
    }
    body.min().array() -= 0.05f;
    body.max().array() += 0.05f;
    size_t on_body = 0, hidden = 0;
    for (size_t k = 0; k < with.size(); ++k) {
        size_t frame_on_body = 0;
        for (size_t i = 0; i < with[k].range.size(); ++i) {
            if (with[k].range[i] == without[k].range[i]) continue;
            if (with[k].range[i] == 0) {  // closer than the sensor's minimum range
                ++hidden;
                continue;
            }
            ASSERT_TRUE(body.contains(with[k].xyz[i]))
                << "frame " << k << " pixel " << i << ": " << with[k].xyz[i].transpose();
            ++frame_on_body;
        }
        EXPECT_GT(frame_on_body, 50u) << "frame " << k;  // in every frame, moving with the rig
        on_body += frame_on_body;
    }
    RecordProperty("points_on_body", int(on_body));
    RecordProperty("returns_hidden", int(hidden));
}

INSTANTIATE_TEST_SUITE_P(Platforms, RigBodyInView,
                         ::testing::Values(Platform::kGo1, Platform::kHandheld),
                         [](const auto& param_info) {
                             return std::string(ToString(param_info.param));
                         });

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::simulate
