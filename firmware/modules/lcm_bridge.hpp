// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The LCM publisher thread and the conversions to the messages of lcmtypes/ (channels and units:
// lcmtypes/README.md): odometry_t per scan, keyframe_t per keyframe, imu_sample_t per Ouster IMU
// sample, go1_state_t per Go1 sample, and the ouster_stats_t and rig_health_t the health thread
// assembles once a period. Publishing (encode, sendmsg) happens here only, off the hot threads.
#pragma once

#include <array>
#include <atomic>
#include <bimslam/bim_pose_t.hpp>
#include <bimslam/go1_state_t.hpp>
#include <bimslam/imu_sample_t.hpp>
#include <bimslam/keyframe_t.hpp>
#include <bimslam/odometry_t.hpp>
#include <bimslam/ouster_stats_t.hpp>
#include <bimslam/rig_health_t.hpp>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "firmware/modules/bim_localizer.hpp"
#include "firmware/modules/rig_types.hpp"
#include "firmware/runtime/latency_histogram.hpp"
#include "firmware/runtime/seqlock.hpp"
#include "firmware/runtime/thread_table.hpp"

namespace lcm {
class LCM;
class LogFile;
}  // namespace lcm

namespace bimslam::rig {

inline constexpr char kOdometryChannel[] = "BIMSLAM_ODOMETRY";
inline constexpr char kKeyframeChannel[] = "BIMSLAM_KEYFRAME";
inline constexpr char kOusterStatsChannel[] = "BIMSLAM_OUSTER_STATS";
inline constexpr char kGo1StateChannel[] = "BIMSLAM_GO1_STATE";
inline constexpr char kImuChannel[] = "BIMSLAM_IMU";
inline constexpr char kRigHealthChannel[] = "BIMSLAM_RIG_HEALTH";
inline constexpr char kBimPoseChannel[] = "BIMSLAM_BIM_POSE";

void ToMessage(const OdometryItem& item, int64_t publish_ns, bimslam::odometry_t* msg);
void ToMessage(const KeyframeItem& item, const keyframes::KeyframeConfig& config,
               int64_t publish_ns, bimslam::keyframe_t* msg);
// The Ouster IMU sample in the IMU's own frame (the ingest rotates it back from the sensor frame).
void ToMessage(const OusterImuItem& item, int64_t publish_ns, bimslam::imu_sample_t* msg);
void ToMessage(const Go1Item& item, int64_t publish_ns, bimslam::go1_state_t* msg);
// A scan's pose in the model: its odometry composed with the localiser's latest T_bim_odom
// (`bim`, of the odometry's segment `segment`; another segment's is not this frame's) and
// T_base_lidar; NaN unless localised in this segment.
void ToMessage(const BimPoseState& bim, const localization::RigMap& map, const OdometryItem& item,
               uint32_t segment, const Eigen::Isometry3d& T_base_lidar, int64_t publish_ns,
               bimslam::bim_pose_t* msg);

struct LcmQueues {
    runtime::SpscQueue<OdometryItem>& odometry;
    runtime::SpscQueue<KeyframeItem>& keyframes;
    runtime::SpscQueue<OusterImuItem>& imu;
    runtime::SpscQueue<Go1Item>& go1;
    runtime::SpscQueue<bimslam::rig_health_t>& health;
    runtime::SpscQueue<bimslam::ouster_stats_t>& ouster_stats;
    runtime::Wakeup& wakeup;
};

// A token bucket on the bytes a replay publishes. UDP multicast has no flow control: a replay at
// --speed max sent keyframes (~325 kB each) faster than lcm-logger could drain its socket, which
// kept 2 of 56. The bucket lets a burst of `burst_bytes` through at once and then holds the
// output to `bytes_per_s`; a message larger than the burst goes out when the bucket is full and
// leaves it in debt. Live runs are never paced.
// Each message costs at least bytes_per_s / messages_per_s: a receiver that falls behind loses
// small messages as readily as large ones (LCM queues a few dozen per subscription).
class PublishPacer {
public:
    PublishPacer(double bytes_per_s, double messages_per_s, double burst_bytes);
    // Sleeps until the bucket is out of debt, then takes `bytes`. Returns the ns it slept.
    int64_t Take(int64_t bytes, int64_t now_mono_ns);

private:
    double rate_;      // bytes per ns
    double min_cost_;  // bytes
    double burst_;     // bytes
    double tokens_;
    int64_t last_ns_ = -1;
};

// Where and how the messages go besides the LCM URL.
struct LcmOutputConfig {
    // A replay's pacing (PublishPacer); 0: none (live runs).
    double pace_bytes_per_s = 0;
    double pace_messages_per_s = 2000;
    // Every message published is also written here, in LCM's log format (lcm::LogFile, as
    // lcm-logger writes it): the lossless record of the run's LCM output. Empty: none.
    std::string log_path;
    // The localiser whose latest step each scan's bim_pose_t carries; nullptr: no bim_pose_t.
    const BimLocalizer* localizer = nullptr;
    Eigen::Isometry3d T_base_lidar = Eigen::Isometry3d::Identity();
};

struct LcmCounters {
    uint64_t published = 0;
    uint64_t failures = 0;  // lcm publish returned an error
    uint64_t odometry = 0, keyframes = 0, imu = 0, go1 = 0, health = 0, ouster_stats = 0;
    uint64_t bim_pose = 0;
    uint64_t logged = 0;   // messages written to the LCM log (LcmOutputConfig::log_path)
    int64_t paced_ns = 0;  // time a replay's output waited for the pacer
};

// One scan's latency split by stage (ScanTimes), in microseconds: last packet -> taken up by the
// ingest thread (receive) -> scan assembled and queued (assemble) -> taken by the odometry thread
// (handoff) -> ScanPipeline::Process done (odometry) -> queued for LCM (outputs) -> odometry_t
// published (publish); then, not a stage, the odometry thread's CPU time in the odometry stage
// (odometry_cpu).
struct LatencyStages {
    static constexpr size_t kStages = 6;
    static constexpr size_t kCount = kStages + 1;
    static constexpr std::array<const char*, kCount> kNames = {
        "receive", "assemble", "handoff", "odometry", "outputs", "publish", "odometry_cpu"};
    std::array<int32_t, kCount> us{};
    static LatencyStages From(const ScanTimes& t, int64_t published_ns);
};

class LcmPublisher {
public:
    // Throws common::Error (kUnavailable) naming the URL when LCM cannot be opened, and
    // common::FileError when the log cannot be created.
    LcmPublisher(const std::string& url, const keyframes::KeyframeConfig& keyframes,
                 LcmQueues queues, const LcmOutputConfig& output = {});
    ~LcmPublisher();

    // Until `producers_done` and every queue is empty.
    void Run(runtime::ThreadStats& stats, const std::atomic<bool>& producers_done);
    LcmCounters counters() const { return counters_.Load(); }
    // The latencies from each scan's last packet to its odometry_t being published, the whole
    // run's, in fixed memory; read after Run returns.
    const runtime::LatencyHistogram& latency() const { return latency_; }
    // The same split by stage (LatencyStages::kNames).
    const std::array<runtime::LatencyHistogram, LatencyStages::kCount>& latency_stages() const {
        return stages_;
    }

private:
    template <typename Msg>
    void Publish(const char* channel, const Msg& msg);
    template <typename Msg>
    void Log(const char* channel, const Msg& msg, int size);

    std::unique_ptr<lcm::LCM> lcm_;
    std::optional<PublishPacer> pacer_;
    std::unique_ptr<lcm::LogFile> log_;
    std::vector<uint8_t> log_buffer_;
    keyframes::KeyframeConfig keyframes_;
    LcmQueues q_;
    const BimLocalizer* localizer_;
    Eigen::Isometry3d T_base_lidar_;
    uint32_t segment_ = 0;  // the odometry's: its resets seen
    LcmCounters c_;
    runtime::Seqlock<LcmCounters> counters_;
    runtime::LatencyHistogram latency_;
    std::array<runtime::LatencyHistogram, LatencyStages::kCount> stages_;
};

}  // namespace bimslam::rig
