// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// changes.bcf (issue 34): the changes of one session that a person must act on, as BCF topics
// (bcf_writer.hpp) with a viewpoint from where the walk saw the change and a snapshot of it
// (snapshot_renderer.hpp). README.md of this folder, "changes.bcf", has the rules: one topic per
// new object, missing element, deviating element (beyond --deviation-tolerance) and moved
// element; type, status and priority from the size of the change; the camera at the nearest
// keyframe that sees the change's centre; the topic's date the session's recording time.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "algorithms/changes/change_detector.hpp"
#include "host_tools/bim/bim_model.hpp"
#include "host_tools/changes/bcf_writer.hpp"
#include "host_tools/changes/change_report.hpp"
#include "host_tools/changes/snapshot_renderer.hpp"

namespace bimslam::change_detection {

// The topic types, statuses and priorities bimslam writes.
inline constexpr const char* kTopicNewObject = "New object";
inline constexpr const char* kTopicMissing = "Missing element";
inline constexpr const char* kTopicDeviating = "Deviation";
inline constexpr const char* kTopicMoved = "Moved element";

struct ChangeTopic {
    BcfTopic topic;         // its snapshot not rendered yet
    SnapshotCamera camera;  // the viewpoint's camera in the mesh's frame
    SnapshotHighlight highlight;
    Eigen::Vector3d target = Eigen::Vector3d::Zero();  // the change's centre, mesh frame
    int keyframe = -1;                                 // the camera's keyframe
};

// The topics of a session's changes, in the order new objects, missing, deviating, moved (each
// in the order of changes.json), numbered from 1. `date_ns`: the recording's time (UNIX ns).
std::vector<ChangeTopic> ChangeTopics(const bim::BimModel& model, const SessionChanges& found,
                                      const changes::ChangeDetectorConfig& config, int64_t date_ns);

struct ChangeBcfOptions {
    BcfVersion version = BcfVersion::k2_1;
    int64_t date_ns = 0;
    std::string model_sha256;       // the project's id
    int width = 640, height = 480;  // the snapshots' (BCF 3.0: at most 1500 on the long side)
};

struct ChangeBcf {
    std::string zip;  // the file's bytes
    size_t topics = 0;
    double topics_s = 0, render_s = 0, png_s = 0, zip_s = 0;
};

// The BCF of a session's changes, snapshots rendered by `renderer` (the model's).
ChangeBcf ChangesBcf(const bim::BimModel& model, const SessionChanges& found,
                     const changes::ChangeDetectorConfig& config, const ChangeBcfOptions& options,
                     SnapshotRenderer& renderer);

// The project of the BCF files of a model: its id from the model's SHA-256 (every visit's and
// recording's file of one model names the same project), its name the model file's, the values
// of 3.0's extensions.xml (the labels: the topic types and the storeys' names).
BcfProject ChangesBcfProject(const bim::BimModel& model, const std::string& model_sha256);

// The session's recording time: its first keyframe's stamp when that is a UNIX time (a capture
// stamped by the sensor's PTP or the host clock, as the simulator's), else session.json's
// `created`, else 0.
int64_t SessionDate(const SessionInput& input);

}  // namespace bimslam::change_detection
