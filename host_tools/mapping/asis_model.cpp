// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/mapping/asis_model.hpp"

#include <array>
#include <vector>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/ply.hpp"
#include "host_tools/bim/ifc_writer.hpp"
#include "host_tools/mapping/map_project.hpp"

namespace bimslam::mapping {
namespace fs = std::filesystem;
using change_detection::IfcAppender;
using nlohmann::json;

namespace {

struct Mesh {
    std::vector<Eigen::Vector3d> vertices;  // the model file's coordinates, metres
    std::vector<std::array<uint32_t, 3>> triangles;
};

// Object `id`'s part of a changes folder's new_objects.ply (changes.json: new_objects[].mesh).
Mesh ObjectMesh(const fs::path& dir, int id) {
    const fs::path file = dir / "changes.json";
    const json changes = json::parse(io::ReadFileToString(file));
    for (const json& o : changes.at("new_objects")) {
        if (o.at("id") != id) continue;
        const json& m = o.at("mesh");
        const io::PlyData ply = io::ReadPly(dir / m.at("file").get<std::string>());
        const size_t v0 = m.at("first_vertex"), nv = m.at("vertices");
        const size_t t0 = m.at("first_triangle"), nt = m.at("triangles");
        if (v0 + nv > ply.vertices.size() || t0 + nt > ply.triangles.size()) {
            throw common::FileError(common::StatusCode::kParseError,
                                    (dir / "new_objects.ply").string(), 0,
                                    "object " + std::to_string(id) + "'s mesh is not in it");
        }
        Mesh mesh;
        for (size_t v = v0; v < v0 + nv; ++v)
            mesh.vertices.push_back(ply.vertices[v].cast<double>());
        for (size_t t = t0; t < t0 + nt; ++t) {
            const auto& tri = ply.triangles[t];
            mesh.triangles.push_back(
                {tri[0] - uint32_t(v0), tri[1] - uint32_t(v0), tri[2] - uint32_t(v0)});
        }
        return mesh;
    }
    throw common::FileError(common::StatusCode::kParseError, file.string(), 0,
                            "no new object " + std::to_string(id));
}

int StoreyIndex(const bim::BimModel& model, const std::string& name) {
    for (size_t s = 0; s < model.storeys.size(); ++s) {
        if (model.storeys[s].name == name) return int(s);
    }
    return -1;
}

std::string LabelOr(const json& j) { return j.is_string() ? IfcAppender::Label(j) : "$"; }

// The objects present after the newest visit, each as its last sighting placed it.
size_t AddObjects(const fs::path& out, const bim::BimModel& model, const json& history,
                  uint64_t seed, IfcAppender* append) {
    size_t n = 0;
    for (const json& o : history.at("objects")) {
        if (o.at("state") != "present") continue;
        const json* placed = nullptr;
        size_t moves = 0;
        for (const json& s : o.at("sightings")) {
            if (s.contains("recording")) placed = &s;
            moves += s.at("status") == "moved";
        }
        if (!placed) continue;
        const std::string id = o.at("id");
        const fs::path dir = VisitDir(out, placed->at("visit")) / "changes" /
                             placed->at("recording").get<std::string>();
        const Mesh mesh = ObjectMesh(dir, placed->at("object"));
        const std::string first = o.at("first_seen"), last = o.at("last_seen");
        const int proxy = append->Proxy(
            mesh.vertices, mesh.triangles, bim::IfcWriter::GlobalId(seed, "as-is object " + id),
            "bimslam object " + id,
            "new since the model: first seen " + first + ", last seen " + last, "new object",
            StoreyIndex(model, o.at("storey")));
        append->PropertySet("object " + id, "bimslam_History",
                            {{"ObjectId", IfcAppender::Label(id)},
                             {"FirstSeen", IfcAppender::Label(first)},
                             {"LastSeen", IfcAppender::Label(last)},
                             {"Moves", IfcAppender::Int(moves)},
                             {"MeshFrom", IfcAppender::Label(placed->at("recording"))}},
                            {proxy});
        ++n;
    }
    return n;
}

// Each observed element's history; returns the GlobalIds missing as is.
std::vector<std::string> AddElementHistories(const json& history, IfcAppender* append) {
    const json& visits = history.at("visits");
    std::vector<std::string> missing;
    for (const json& e : history.at("elements")) {
        if (e.at("last_observed").is_null()) continue;
        std::string by_visit;
        size_t observed = 0;
        for (size_t v = 0; v < visits.size(); ++v) {
            const std::string verdict = e.at("verdicts").at(v);
            by_visit += (v ? "; " : "") + visits[v].at("label").get<std::string>() + " " + verdict;
            observed += verdict != "not_observed";
        }
        IfcAppender::Values values = {{"AsIs", IfcAppender::Label(e.at("last_verdict"))},
                                      {"LastObserved", LabelOr(e.at("last_observed"))},
                                      {"FirstSeenBuilt", LabelOr(e.at("first_seen_built"))},
                                      {"LastSeenBuilt", LabelOr(e.at("last_seen_built"))},
                                      {"VisitsObserved", IfcAppender::Int(observed)},
                                      {"VerdictsByVisit", IfcAppender::Text(by_visit)}};
        if (!e.at("deviations").empty()) {
            const json& d = e.at("deviations").back();
            values.push_back({"LastDeviation", append->Length(d.at("offset_norm_m"))});
            values.push_back({"LastDeviationVisit", IfcAppender::Label(d.at("visit"))});
        }
        const std::string id = e.at("global_id");
        append->ElementPropertySet(id, e.at("class"), "history " + id, "bimslam_History", values);
        if (e.at("last_verdict") == "missing") missing.push_back(id);
    }
    return missing;
}

}  // namespace

change_detection::IfcUpdate AsIsIfc(const fs::path& out, const std::string& name,
                                    const std::string& text, const bim::BimModel& model,
                                    const json& history, uint64_t seed) {
    IfcAppender append(name, text, model, seed);
    AddObjects(out, model, history, seed, &append);
    append.Contain("as-is");
    const std::vector<std::string> missing = AddElementHistories(history, &append);
    const json& visits = history.at("visits");
    const std::string newest = visits.empty() ? std::string() : visits.back().value("label", "");
    append.Group("missing", "bimslam missing elements",
                 "elements missing as of visit " + newest + " (bimslam map)", missing);
    return append.Finish("as-is");
}

}  // namespace bimslam::mapping
