// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam bcf info: what a BCF file holds (ours, or one a BIM tool wrote or sent back), read and
// checked by host_tools/changes/bcf_reader.hpp.
#include <iostream>
#include <nlohmann/json.hpp>

#include "host_tools/changes/bcf_reader.hpp"
#include "host_tools/cli/command.hpp"

namespace bimslam::cli {
namespace {

using change_detection::BcfCamera;
using change_detection::BcfFile;
using change_detection::BcfReadTopic;
using change_detection::BcfViewpoint;

const char* CameraName(BcfCamera c) {
    switch (c) {
        case BcfCamera::kPerspective: return "perspective";
        case BcfCamera::kOrthogonal: return "orthogonal";
        case BcfCamera::kNone: break;
    }
    return "none";
}

nlohmann::json ViewpointJson(const BcfViewpoint& v) {
    nlohmann::json j{{"guid", v.guid},
                     {"camera", CameraName(v.camera)},
                     {"selected", v.selected},
                     {"default_visibility", v.default_visibility},
                     {"visibility_exceptions", v.visibility_exceptions},
                     {"snapshot_bytes", v.snapshot_png.size()}};
    if (v.camera != BcfCamera::kNone) {
        j["eye"] = {v.eye.x(), v.eye.y(), v.eye.z()};
        j["direction"] = {v.direction.x(), v.direction.y(), v.direction.z()};
        j["up"] = {v.up.x(), v.up.y(), v.up.z()};
        j["aspect"] = v.aspect;
        if (v.camera == BcfCamera::kPerspective) j["fov_deg"] = v.fov_deg;
        else j["view_to_world_scale"] = v.view_to_world_scale;
    }
    nlohmann::json colors = nlohmann::json::array();
    for (const auto& [color, ids] : v.colors) colors.push_back({{"color", color}, {"components", ids}});
    j["colors"] = colors;
    return j;
}

nlohmann::json TopicJson(const BcfReadTopic& r) {
    const auto& t = r.topic;
    nlohmann::json j{{"guid", t.guid},         {"index", t.index},
                     {"type", t.type},         {"status", t.status},
                     {"priority", t.priority}, {"title", t.title},
                     {"description", t.description}, {"labels", t.labels},
                     {"creation_date", t.creation_date}, {"author", t.author},
                     {"modified_date", r.modified_date}, {"due_date", r.due_date},
                     {"assigned_to", r.assigned_to},   {"reference_file", t.reference_file}};
    j["viewpoints"] = nlohmann::json::array();
    for (const BcfViewpoint& v : r.viewpoints) j["viewpoints"].push_back(ViewpointJson(v));
    j["comments"] = nlohmann::json::array();
    for (const auto& c : r.comments) {
        j["comments"].push_back({{"guid", c.guid},
                                 {"date", c.date},
                                 {"author", c.author},
                                 {"text", c.text},
                                 {"viewpoint", c.viewpoint_guid}});
    }
    return j;
}

int Info(const std::string& path, bool as_json) {
    const BcfFile f = change_detection::ReadBcf(path);
    if (as_json) {
        nlohmann::json j{{"path", path},
                         {"version", change_detection::ToString(f.version)},
                         {"project", {{"id", f.project.id}, {"name", f.project.name}}}};
        j["topics"] = nlohmann::json::array();
        for (const BcfReadTopic& t : f.topics) j["topics"].push_back(TopicJson(t));
        std::cout << j.dump(2) << "\n";
        return kExitOk;
    }
    std::cout << "BCF " << change_detection::ToString(f.version) << "  " << path << "\n";
    if (!f.project.name.empty() || !f.project.id.empty())
        std::cout << "project      " << f.project.name << " (" << f.project.id << ")\n";
    std::cout << "topics       " << f.topics.size() << "\n";
    for (const BcfReadTopic& r : f.topics) {
        const auto& t = r.topic;
        size_t selected = 0;
        for (const BcfViewpoint& v : r.viewpoints) selected += v.selected.size();
        std::cout << "  " << t.guid << "  " << (t.type.empty() ? "-" : t.type) << " / "
                  << (t.status.empty() ? "-" : t.status) << " / "
                  << (t.priority.empty() ? "-" : t.priority) << "  " << t.title << "\n"
                  << "      created " << t.creation_date
                  << (t.author.empty() ? "" : " by " + t.author) << "; " << r.viewpoints.size()
                  << " viewpoint(s), " << selected << " selected component(s), "
                  << r.comments.size() << " comment(s)\n";
    }
    return kExitOk;
}

}  // namespace

void AddBcfCommands(CLI::App& app, int& exit_code) {
    CLI::App* bcf = app.add_subcommand("bcf", "BCF issue files (BIM Collaboration Format 2.1, 3.0)");
    bcf->require_subcommand(1);
    CLI::App* info = bcf->add_subcommand(
        "info",
        "Read and check a BCF file (bimslam's changes.bcf or another BIM tool's): its version, "
        "project and topics with their type, status, priority, viewpoints and comments. Exit 2 "
        "when it is not a BCF 2.1 or 3.0 zip or is damaged, naming the entry and what is wrong.");
    auto path = std::make_shared<std::string>();
    auto as_json = std::make_shared<bool>(false);
    info->add_option("FILE", *path, "a .bcf / .bcfzip file")->required();
    info->add_flag("--json", *as_json,
                   "machine-readable output: every topic's words, viewpoints (camera, selected, "
                   "coloured and visibility components, snapshot size) and comments");
    info->callback([path, as_json, &exit_code] {
        exit_code = Run([&] { return Info(*path, *as_json); });
    });
}

}  // namespace bimslam::cli
