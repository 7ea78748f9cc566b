// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/report/report_visits.hpp"

#include <string>
#include <system_error>
#include <unordered_map>
#include <vector>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/trajectory.hpp"
#include "host_tools/report/report_geometry.hpp"

namespace bimslam::report {
namespace fs = std::filesystem;
using nlohmann::json;

json VisitWalks(const fs::path& out, const json& summary, const bim::BimModel& model,
                size_t max_points) {
    if (!summary.contains("visits")) return nullptr;
    json visits = json::array();
    for (const json& v : summary.at("visits")) {
        json recordings = json::array(), walks = json::array();
        for (const json& r : v.at("recordings")) {
            const std::string name = r.at("name");
            const json verdict = r.value("anchor_verdict", json(nullptr));
            recordings.push_back({{"name", name}, {"anchor_verdict", verdict}});
            if (verdict != "anchored" && verdict != "anchored-in-parts") continue;
            const fs::path file =
                out / v.at("dir").get<std::string>() / "anchor" / name / "trajectory_bim.tum";
            std::error_code ec;
            if (!fs::exists(file, ec)) continue;
            std::vector<Eigen::Vector3d> positions;
            for (const io::StampedPose& p : io::ReadTum(file)) positions.push_back(p.translation);
            walks.push_back({{"name", name}, {"runs", StoreyRuns(positions, model, max_points)}});
        }
        visits.push_back({{"label", v.at("label")},
                          {"start", v.at("start")},
                          {"recordings", recordings},
                          {"walks", walks}});
    }
    return visits;
}

json HistoryForPage(const fs::path& out, const bim::BimModel& model) {
    const fs::path file = out / "history.json";
    std::error_code ec;
    if (!fs::exists(file, ec)) return nullptr;
    json history;
    try {
        history = json::parse(io::ReadFileToString(file));
    } catch (const json::exception& e) {
        throw common::FileError(common::StatusCode::kParseError, file.string(), 0, e.what());
    }
    std::unordered_map<std::string, size_t> index;
    for (size_t i = 0; i < model.elements.size(); ++i) index[model.elements[i].global_id] = i;
    for (json& e : history.at("elements")) {
        const auto it = index.find(e.at("global_id").get<std::string>());
        if (it == index.end()) continue;
        const Eigen::AlignedBox3d b = ElementBox(model, it->second);
        if (b.isEmpty()) continue;
        e["min"] = {b.min().x(), b.min().y(), b.min().z()};
        e["max"] = {b.max().x(), b.max().y(), b.max().z()};
    }
    return history;
}

}  // namespace bimslam::report
