// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Session data: the on-disk contract between the rig, the BIM generator and the host tools
// (specs/session-data.md). A session is a pose graph plus, per keyframe, its cloud and its Scan
// Context descriptor; the file names are those SC-A-LOAM writes and LT-mapper reads.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/common/point_cloud.hpp"
#include "algorithms/common/se3.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/trajectory.hpp"

namespace bimslam::io {

// rings x sectors, the layout of algorithms/scancontext's Descriptor.
using DescriptorMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

inline constexpr int kSessionFormatVersion = 1;

// session.json. Written last: its presence marks a complete session.
struct SessionManifest {
    std::string source = "rig";  // "rig" | "bim" | "simulation"
    std::string created;         // ISO 8601 UTC; the writer fills it when empty
    struct Sensor {
        std::string model = "OS-1-32";
        int beams = 32;
        int columns = 1024;
        std::string metadata_file;  // the Ouster metadata JSON it came from, if any
    } sensor;
    std::string world_frame = "odom";  // frame of optimized_poses.txt: "odom", "bim", ...
    struct KeyframeRule {
        double distance_m = 1.0;
        double angle_deg = 10.0;
    } keyframe;
    struct Descriptor {
        std::string kind = "indoor";  // "indoor" | "outdoor"
        int rings = 20;
        int sectors = 60;
        double max_radius_m = 10.0;
        // The indoor cell rule: occupied with >= min_points spanning >= min_z_span_m, the span
        // measured as `cell_rule` says (algorithms/scancontext/config.hpp): "z_span" or
        // "z_stack"; a file that names none was written before z_stack, with z_span.
        int min_points = 0;
        double min_z_span_m = 0.0;
        std::string cell_rule = "z_stack";
    } descriptor;
    struct Counts {
        size_t keyframes = 0;
        size_t scans = 0;
    } counts;
    // BIM sessions only: the model the reference scans were simulated from.
    struct Model {
        std::string file;
        std::string sha256;
        std::vector<std::string> storeys;
    };
    std::optional<Model> model;
    // session.json "clocks": {"host_minus_sensor_ns"}: the recording host's UNIX time minus the
    // sensor clock (times.txt + this = UNIX time, within the network latency), when the recorder
    // knew it (`bimslam odometry`, `bimslam map`); absent otherwise. map_bim.las's GPS times.
    std::optional<int64_t> host_minus_sensor_ns;
};

// One keyframe. stamp_ns (times.txt) is the start of the keyframe's scan in the sensor clock;
// the cloud's per-point times count from it, and the reader sets cloud.stamp to it.
struct SessionKeyframe {
    int64_t stamp_ns = 0;                                             // times.txt
    Eigen::Isometry3d T_world_lidar = Eigen::Isometry3d::Identity();  // optimized_poses.txt
    std::optional<Eigen::Isometry3d> T_odom_lidar;                    // odom_poses.txt (rig)
    DescriptorMatrix descriptor;                                      // SCDs/NNNNNN.scd
    common::PointCloud cloud;  // Scans/NNNNNN.pcd, in this keyframe's lidar frame; empty when
                               // the reader was asked not to load clouds
};

// An edge of singlesession_posegraph.g2o: the measured T_from_to with its information matrix
// over [x y z rx ry rz] (translation first, as g2o's EDGE_SE3:QUAT).
struct SessionEdge {
    uint32_t from = 0;
    uint32_t to = 0;
    Eigen::Isometry3d T_from_to = Eigen::Isometry3d::Identity();
    common::Matrix6d information = common::Matrix6d::Identity();
};

struct Session {
    SessionManifest manifest;
    std::vector<SessionKeyframe> keyframes;
    std::vector<SessionEdge> edges;
    std::vector<StampedPose> trajectory;  // trajectory.tum: every scan, not only keyframes
    // False when session.json was missing and the session was recovered up to its last complete
    // keyframe; `notes` then says how many keyframes were recovered and what was dropped.
    bool complete = true;
    std::vector<std::string> notes;
};

// Why a rig's session may hold no keyframe at all: the rig writes none while its disk has less
// than session.min_free_mb free (firmware/modules/session_recorder.hpp), and counts them in its
// summary's keyframes_skipped_disk. Said with every "no keyframes" error.
inline constexpr const char* kNoKeyframesHint =
    "a rig writes none while its disk has less than session.min_free_mb free: see its summary's "
    "keyframes_skipped_disk";

struct SessionReadOptions {
    bool load_clouds = true;
    // Read a session without session.json (cut off by power loss or a full disk) up to its last
    // complete keyframe. When false such a session is an error.
    bool allow_recovery = true;
};

// Reads and validates a session. Throws common::FileError naming the file (and line) on a
// missing file, a count mismatch between files, a malformed number, a non-finite value, a
// descriptor of the wrong size, or a manifest that is not a bimslam session.
Session ReadSession(const std::filesystem::path& dir, const SessionReadOptions& options = {});

// times.txt: one timestamp (seconds) per line, parsed exactly to nanoseconds. Throws
// common::FileError naming the file and line.
std::vector<int64_t> ReadTimes(const std::filesystem::path& path);
std::vector<int64_t> ParseTimes(const std::string& name, std::string_view text);

// The path of keyframe i's files.
std::filesystem::path KeyframeCloudPath(const std::filesystem::path& dir, size_t index);
std::filesystem::path KeyframeDescriptorPath(const std::filesystem::path& dir, size_t index);

// SCD files: rings lines of sectors numbers. Reading checks the size when expected_rings/sectors
// are non-zero.
void WriteScd(const std::filesystem::path& path, const DescriptorMatrix& descriptor);
DescriptorMatrix ReadScd(const std::filesystem::path& path, int expected_rings = 0,
                         int expected_sectors = 0);

struct SessionWriterOptions {
    // Replace an existing session at the same path. Without it the writer refuses. Even with it,
    // a non-empty folder that is not a session is never deleted.
    bool overwrite = false;
    // Rewrite the line-oriented files every this many keyframes. 1 (the rig) loses nothing but
    // the keyframe being written on power loss; offline generators may batch.
    size_t flush_every = 1;
    // Sync every file as it is written (the rig: a power loss loses at most the keyframe being
    // written), or only once in Finish(), before session.json (offline generators, which can be
    // re-run: each fsync costs milliseconds). session.json means complete and durable either way.
    bool sync_each_file = true;
};

// Writes a session incrementally, so that a cut-off session stays readable (specs "Rules"):
// each keyframe's cloud and descriptor first, then the line files, each file atomically; the
// manifest last, in Finish().
class SessionWriter {
public:
    SessionWriter(std::filesystem::path dir, SessionManifest manifest,
                  SessionWriterOptions options = {});
    // Without Finish() the session stays incomplete (no session.json): the destructor flushes
    // what it can, and readers recover it up to its last complete keyframe. An exception that
    // unwinds past a writer must not make a half-made session look complete.
    ~SessionWriter();
    SessionWriter(const SessionWriter&) = delete;
    SessionWriter& operator=(const SessionWriter&) = delete;

    // Writes keyframe i = number of keyframes so far; returns i.
    size_t AddKeyframe(const SessionKeyframe& keyframe);
    // An odometry or intra-session loop edge between keyframes already added.
    void AddEdge(const SessionEdge& edge);
    // A scan's pose for trajectory.tum (every scan, in time order).
    void AddScanPose(const StampedPose& pose);
    // The rig in the building's model (issue 35): a scan's live pose in the model for
    // trajectory_bim_live.tum (T_bim_lidar: its odometry composed with the relocaliser's
    // T_bim_odom then; scans while localised, in time order), and a change of the relocaliser's
    // state for localization_states.csv (`t_s state consistent_loops hypotheses storey`, the
    // keyframe's time in seconds, the storey's name the rest of the line, - for none). The first
    // call of either makes both files part of the session.
    void AddLivePose(const StampedPose& pose);
    void AddLocalizationState(int64_t stamp_ns, std::string_view state, size_t consistent_loops,
                              size_t hypotheses, std::string_view storey);
    // Appends what was added since the last flush to the line-oriented files now.
    void Flush();
    // Flushes and writes session.json. Further calls are errors.
    void Finish();
    // Sets session.json's clocks.host_minus_sensor_ns (SessionManifest), e.g. once the offset has
    // been measured; before Finish().
    void SetHostMinusSensorNs(int64_t ns) { manifest_.host_minus_sensor_ns = ns; }

    size_t keyframe_count() const { return keyframes_; }
    // The text held until the next flush (bytes): what the writer's memory holds of the session.
    size_t pending_bytes() const;
    const std::filesystem::path& dir() const { return dir_; }

private:
    // The line files' text since the last flush: each item is formatted once, when it is added,
    // and a flush appends it to its file and clears it. The writer holds the text of one flush
    // period, not the session's (keeping the whole text and rewriting every file at each flush
    // grew the rig by 0.35 MB a minute of walk). The pose graph's text is its vertices and edges
    // in the order they were added: an edge joins keyframes added before it.
    struct Text {
        std::string times, world, odom, graph, trajectory;
        std::string live, states;  // trajectory_bim_live.tum, localization_states.csv
    };
    struct Files {
        std::optional<AppendFile> times, world, odom, graph, trajectory, live, states;
    };
    // Appends `text` to `file` (created first if `create`; nothing until then) and clears it.
    void Append(std::optional<AppendFile>& file, const char* name, std::string& text, bool create);
    std::filesystem::path dir_;
    SessionManifest manifest_;
    SessionWriterOptions options_;
    Text text_;
    Files files_;
    size_t keyframes_ = 0;
    bool keyframes_have_odom_ = false;  // the first keyframe's; every keyframe's must agree
    size_t scans_ = 0;
    int64_t last_scan_ns_ = 0;
    size_t unflushed_ = 0;
    bool finished_ = false;
    bool localization_ = false;  // AddLivePose or AddLocalizationState was called
    Sync sync() const { return options_.sync_each_file ? Sync::kNow : Sync::kDeferred; }
};

// session.json to and from text (exposed for tests and `bimslam session info --json`).
std::string SerializeManifest(const SessionManifest& manifest);
SessionManifest ParseManifest(const std::string& name, const std::string& text);

}  // namespace bimslam::io
