// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The demo's rig: a capture run through `bimslam-rig replay` as a separate process (the
// on-board firmware, its threads, queues and LCM, as on the rig), with `lcm-logger` recording
// what it publishes. Host tools may not link the firmware (ARCHITECTURE.md, "Layers"): they run
// its executable, found next to this one.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace bimslam::cli {

struct RigReplayRun {
    std::filesystem::path session;  // the session the rig wrote
    std::filesystem::path lcm_log;  // empty when lcm-logger is not installed
    size_t scans = 0, keyframes = 0, scans_dropped = 0;
    double wall_s = 0;
    // Of wall_s, the time its LCM output waited for the replay's pacer (firmware/app/README.md:
    // paced so that lcm-logger keeps up). At full speed the frames' latency to LCM counts that
    // wait, not the rig's work, so the demo does not print it (rig_benchmark measures it at 1x).
    double lcm_paced_s = 0;
};

// Replays `capture` at full speed (lossless) into a session under `work_dir`/sessions, recording
// LCM into `work_dir`/rig.lcmlog. Throws common::Error naming the command when it fails.
RigReplayRun RunRigReplay(const std::filesystem::path& capture,
                          const std::filesystem::path& work_dir);

}  // namespace bimslam::cli
