// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam session info: what a session holds, and whether it is complete and valid.
#include <iostream>
#include <nlohmann/json.hpp>

#include "algorithms/common/se3.hpp"
#include "algorithms/io/session.hpp"
#include "host_tools/anchor/anchor_session.hpp"
#include "host_tools/cli/command.hpp"

namespace bimslam::cli {
namespace {

struct Summary {
    double duration_s = 0.0;
    double path_length_m = 0.0;
    Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();
};

Summary Summarise(const io::Session& s) {
    Summary out;
    if (s.keyframes.empty()) return out;
    out.duration_s = 1e-9 * double(s.keyframes.back().stamp_ns - s.keyframes.front().stamp_ns);
    out.min = out.max = s.keyframes.front().T_world_lidar.translation();
    for (size_t i = 1; i < s.keyframes.size(); ++i) {
        const Eigen::Vector3d p = s.keyframes[i].T_world_lidar.translation();
        out.path_length_m += (p - s.keyframes[i - 1].T_world_lidar.translation()).norm();
        out.min = out.min.cwiseMin(p);
        out.max = out.max.cwiseMax(p);
    }
    return out;
}

int Info(const std::string& dir, bool json) {
    // A session of SC-A-LOAM, LT-mapper or FAST-LIO-SC (Scans/, poses, times; no session.json,
    // SCDs or g2o) is read the way `bimslam anchor` reads it, saying what it derives.
    const bool foreign = anchor::IsForeignSession(dir);
    io::Session s;
    if (foreign) {
        anchor::LoadOptions options;
        options.load_clouds = false;
        options.compute_descriptors = false;
        anchor::AnchorSession a = anchor::LoadAnchorSession(dir, options);
        s = std::move(a.session);
        s.notes = std::move(a.notes);
    } else {
        s = io::ReadSession(dir, {.load_clouds = false, .allow_recovery = true});
    }
    const Summary sum = Summarise(s);
    const auto& m = s.manifest;
    if (json) {
        nlohmann::json j;
        j["path"] = dir;
        j["complete"] = s.complete;
        j["layout"] = foreign ? "sc-a-loam" : "bimslam";
        // A recovered session has no manifest: what it would have said is unknown.
        j["source"] = s.complete ? nlohmann::json(m.source) : nlohmann::json(nullptr);
        j["world_frame"] = s.complete ? nlohmann::json(m.world_frame) : nlohmann::json(nullptr);
        j["keyframes"] = s.keyframes.size();
        j["scans"] = s.trajectory.size();
        j["edges"] = s.edges.size();
        j["descriptor"] = {{"kind", m.descriptor.kind},
                           {"rings", m.descriptor.rings},
                           {"sectors", m.descriptor.sectors},
                           {"max_radius_m", m.descriptor.max_radius_m}};
        j["sensor"] = {
            {"model", m.sensor.model}, {"beams", m.sensor.beams}, {"columns", m.sensor.columns}};
        j["duration_s"] = sum.duration_s;
        j["path_length_m"] = sum.path_length_m;
        j["bbox_m"] = {{sum.min.x(), sum.min.y(), sum.min.z()},
                       {sum.max.x(), sum.max.y(), sum.max.z()}};
        j["notes"] = s.notes;
        std::cout << j.dump(2) << "\n";
        return kExitOk;
    }
    std::cout << "session      " << dir
              << (foreign ? "  (SC-A-LOAM/LT-mapper layout)"
                          : (s.complete ? "" : "  (INCOMPLETE: recovered)"))
              << "\n";
    if (foreign) {
        std::cout << "source       another tool: no session.json, SCDs/ or pose graph\n";
    } else if (s.complete) {
        std::cout << "source       " << m.source << ", poses in frame '" << m.world_frame << "'"
                  << (m.created.empty() ? "" : ", created " + m.created) << "\n"
                  << "sensor       " << m.sensor.model << " " << m.sensor.beams << "x"
                  << m.sensor.columns << "\n";
    } else {
        std::cout << "source       unknown: session.json is missing\n";
    }
    std::cout << "keyframes    " << s.keyframes.size() << " over " << sum.path_length_m << " m and "
              << sum.duration_s << " s\n"
              << "scans        " << s.trajectory.size() << " poses in trajectory.tum\n"
              << "edges        " << s.edges.size()
              << (foreign ? " derived from the poses\n" : " in singlesession_posegraph.g2o\n");
    if (!foreign) {
        std::cout << "descriptor   Scan Context " << m.descriptor.rings << "x"
                  << m.descriptor.sectors;
    }
    if (s.complete)
        std::cout << ", " << m.descriptor.kind << ", " << m.descriptor.max_radius_m << " m";
    if (!foreign) std::cout << "\n";
    for (const std::string& note : s.notes) std::cout << "note         " << note << "\n";
    return kExitOk;
}

}  // namespace

void AddSessionCommands(CLI::App& app, int& exit_code) {
    CLI::App* session = app.add_subcommand("session",
                                           "Inspect session data "
                                           "(specs/session-data.md)");
    session->require_subcommand(1);
    CLI::App* info = session->add_subcommand(
        "info", "Read and validate a session; print what it holds. Exit 2 when it is damaged.");
    auto dir = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    info->add_option("SESSION", *dir, "session folder")->required();
    info->add_flag("--json", *json, "machine-readable output");
    info->callback([dir, json, &exit_code] { exit_code = Run([&] { return Info(*dir, *json); }); });
}

}  // namespace bimslam::cli
