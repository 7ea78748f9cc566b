// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include <cstdio>
#include <ctime>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/g2o.hpp"
#include "algorithms/io/pcd.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/io/text_reader.hpp"

namespace bimslam::io {
namespace {
using common::FileError;
using common::StatusCode;
namespace fs = std::filesystem;

std::string IsoUtcNow() {
    const std::time_t now = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&now, &tm);
    char buf[32];
    std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}

bool LooksLikeSession(const fs::path& dir) {
    return fs::exists(dir / "session.json") || fs::is_directory(dir / "Scans") ||
           fs::is_directory(dir / "SCDs");
}

// Refuses to replace anything unless asked, and never deletes a folder that is not a session.
void PrepareFolder(const fs::path& dir, bool overwrite) {
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_empty(dir, ec)) {
        if (!overwrite) {
            throw FileError(StatusCode::kAlreadyExists, dir.string(), 0,
                            "already exists and is not empty; choose another folder or pass the "
                            "overwrite flag to replace the session in it");
        }
        if (!LooksLikeSession(dir)) {
            throw FileError(StatusCode::kAlreadyExists, dir.string(), 0,
                            "holds files but no session (no session.json, Scans/ or SCDs/); "
                            "refusing to delete it even with the overwrite flag");
        }
        fs::remove_all(dir, ec);
        if (ec) {
            throw FileError(StatusCode::kIoError, dir.string(), 0,
                            "cannot remove the old session: " + ec.message());
        }
    }
    for (const fs::path& p : {dir, dir / "Scans", dir / "SCDs"}) {
        fs::create_directories(p, ec);
        if (ec) {
            throw FileError(StatusCode::kIoError, p.string(), 0,
                            "cannot create folder: " + ec.message());
        }
    }
}
}  // namespace

fs::path KeyframeCloudPath(const fs::path& dir, size_t index) {
    char name[32];
    std::snprintf(name, sizeof(name), "%06zu.pcd", index);
    return dir / "Scans" / name;
}

fs::path KeyframeDescriptorPath(const fs::path& dir, size_t index) {
    char name[32];
    std::snprintf(name, sizeof(name), "%06zu.scd", index);
    return dir / "SCDs" / name;
}

namespace {
std::string SerializeScd(const DescriptorMatrix& d) {
    std::string out;
    for (Eigen::Index r = 0; r < d.rows(); ++r) {
        for (Eigen::Index c = 0; c < d.cols(); ++c) {
            if (c > 0) out += ' ';
            out += FormatFloat(d(r, c));
        }
        out += '\n';
    }
    return out;
}
}  // namespace

void WriteScd(const fs::path& path, const DescriptorMatrix& d) {
    WriteFileAtomic(path, SerializeScd(d));
}

SessionWriter::SessionWriter(fs::path dir, SessionManifest manifest, SessionWriterOptions options)
    : dir_(std::move(dir)), manifest_(std::move(manifest)), options_(options) {
    // Validate through the reader's own rules, so the writer cannot produce what it would reject.
    ParseManifest("manifest of " + dir_.string(), SerializeManifest(manifest_));
    if (options_.flush_every == 0) options_.flush_every = 1;
    PrepareFolder(dir_, options_.overwrite);
}

SessionWriter::~SessionWriter() {
    if (finished_) return;
    try {
        Flush();
    } catch (...) {  // NOLINT(bugprone-empty-catch): a destructor must not throw; data is on disk
    }
}

size_t SessionWriter::AddKeyframe(const SessionKeyframe& kf) {
    const size_t i = keyframes_;
    const std::string what = dir_.string() + " keyframe " + std::to_string(i);
    if (finished_) throw common::Error(StatusCode::kInvalidArgument, what + ": session finished");
    if (kf.descriptor.rows() != manifest_.descriptor.rings ||
        kf.descriptor.cols() != manifest_.descriptor.sectors) {
        throw common::Error(StatusCode::kInvalidArgument,
                            what + ": descriptor is " + std::to_string(kf.descriptor.rows()) + "x" +
                                std::to_string(kf.descriptor.cols()) + ", the manifest says " +
                                std::to_string(manifest_.descriptor.rings) + "x" +
                                std::to_string(manifest_.descriptor.sectors));
    }
    if (!common::IsValidRigid(kf.T_world_lidar, 1e-6) ||
        (kf.T_odom_lidar && !common::IsValidRigid(*kf.T_odom_lidar, 1e-6))) {
        throw common::Error(StatusCode::kInvalidArgument, what + ": pose is not a rigid transform");
    }
    if (i > 0 && kf.T_odom_lidar.has_value() != keyframes_have_odom_) {
        throw common::Error(StatusCode::kInvalidArgument,
                            what + ": odometry poses must be given for all keyframes or none");
    }
    if (!kf.cloud.ChannelsConsistent()) {
        throw common::Error(StatusCode::kInvalidArgument, what + ": cloud channels differ in size");
    }
    // Cloud and descriptor first: a keyframe counts only once its lines are flushed after them.
    const fs::path cloud_path = KeyframeCloudPath(dir_, i);
    std::string bytes;
    try {
        bytes = SerializePcd(kf.cloud, PcdEncoding::kBinary);
    } catch (const common::Error& e) {
        throw common::FileError(e.code(), cloud_path.string(), 0, e.what());
    }
    WriteFileAtomic(cloud_path, bytes, sync());
    WriteFileAtomic(KeyframeDescriptorPath(dir_, i), SerializeScd(kf.descriptor), sync());
    text_.times += FormatNsAsSeconds(kf.stamp_ns) + "\n";
    AppendKittiLine(text_.world, kf.T_world_lidar);
    if (kf.T_odom_lidar) AppendKittiLine(text_.odom, *kf.T_odom_lidar);
    AppendG2oVertex(text_.graph, i, kf.T_world_lidar);
    if (i == 0) keyframes_have_odom_ = kf.T_odom_lidar.has_value();
    ++keyframes_;
    if (++unflushed_ >= options_.flush_every) Flush();
    return i;
}

void SessionWriter::AddEdge(const SessionEdge& e) {
    if (e.from >= keyframes_ || e.to >= keyframes_ || e.from == e.to) {
        throw common::Error(StatusCode::kInvalidArgument,
                            dir_.string() + ": edge " + std::to_string(e.from) + " -> " +
                                std::to_string(e.to) + " does not join two written keyframes");
    }
    if (!e.information.allFinite() || !common::IsValidRigid(e.T_from_to, 1e-6)) {
        throw common::Error(StatusCode::kInvalidArgument,
                            dir_.string() + ": edge " + std::to_string(e.from) + " -> " +
                                std::to_string(e.to) + " has a non-finite or non-rigid value");
    }
    AppendG2oEdge(text_.graph, e);
}

void SessionWriter::AddScanPose(const StampedPose& pose) {
    if (scans_ > 0 && pose.stamp_ns < last_scan_ns_) {
        throw common::Error(StatusCode::kInvalidArgument,
                            dir_.string() + ": scan poses must come in time order");
    }
    AppendTumLine(text_.trajectory, pose);
    last_scan_ns_ = pose.stamp_ns;
    ++scans_;
}

void SessionWriter::AddLivePose(const StampedPose& pose) {
    localization_ = true;
    AppendTumLine(text_.live, pose);
}

void SessionWriter::AddLocalizationState(int64_t stamp_ns, std::string_view state,
                                         size_t consistent_loops, size_t hypotheses,
                                         std::string_view storey) {
    localization_ = true;
    text_.states += FormatNsAsSeconds(stamp_ns) + ' ' + std::string(state) + ' ' +
                    std::to_string(consistent_loops) + ' ' + std::to_string(hypotheses) + ' ' +
                    (storey.empty() ? std::string("-") : std::string(storey)) + '\n';
}

void SessionWriter::Flush() {
    Append(files_.times, "times.txt", text_.times, true);
    Append(files_.world, "optimized_poses.txt", text_.world, true);
    // A rig session has odometry poses even before its first keyframe (the reader requires the
    // file of a complete rig session; a full disk can leave it without keyframes).
    Append(files_.odom, "odom_poses.txt", text_.odom,
           !text_.odom.empty() || manifest_.source == "rig");
    Append(files_.graph, "singlesession_posegraph.g2o", text_.graph, true);
    Append(files_.trajectory, "trajectory.tum", text_.trajectory, true);
    Append(files_.live, "trajectory_bim_live.tum", text_.live, localization_);
    if (localization_ && !files_.states) {  // a new file starts with its header
        text_.states.insert(0, "# t_s state consistent_loops hypotheses storey\n");
    }
    Append(files_.states, "localization_states.csv", text_.states, localization_);
    unflushed_ = 0;
}

size_t SessionWriter::pending_bytes() const {
    return text_.times.size() + text_.world.size() + text_.odom.size() + text_.graph.size() +
           text_.trajectory.size() + text_.live.size() + text_.states.size();
}

void SessionWriter::Append(std::optional<AppendFile>& file, const char* name, std::string& text,
                           bool create) {
    if (!file) {
        if (!create) return;
        file.emplace(dir_ / name);
    }
    // On a failure the text stays, to be appended by the next flush (AppendFile cut it back off).
    file->Append(text, sync());
    text.clear();
}

void SessionWriter::Finish() {
    if (finished_) {
        throw common::Error(StatusCode::kInvalidArgument, dir_.string() + ": already finished");
    }
    Flush();
    manifest_.counts.keyframes = keyframes_;
    manifest_.counts.scans = scans_;
    if (manifest_.created.empty()) manifest_.created = IsoUtcNow();
    if (!options_.sync_each_file) SyncFileSystem(dir_);
    WriteFileAtomic(dir_ / "session.json", SerializeManifest(manifest_));
    finished_ = true;
}

}  // namespace bimslam::io
