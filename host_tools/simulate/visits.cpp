// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/simulate/visits.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>

#include "algorithms/common/status.hpp"
#include "algorithms/common/utc_time.hpp"
#include "algorithms/io/file_util.hpp"
#include "host_tools/simulate/world.hpp"

namespace bimslam::simulate {
namespace {
using nlohmann::json;

json Xyz(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// (-180, 180]
double WrapYawDeg(double a) {
    a = std::fmod(a, 360.0);
    if (a <= -180.0) a += 360.0;
    if (a > 180.0) a -= 360.0;
    return a;
}

// An added object as the scenario places it: its reference point (a box's or mirror's centre, a
// cylinder's base, a mesh's position), its yaw, and a text of its shape (two objects of one name
// are the same object only with the same shape).
struct Placed {
    std::string kind, shape;
    Eigen::Vector3d at = Eigen::Vector3d::Zero();
    double yaw_deg = 0;
};

std::string ShapeText(std::initializer_list<double> numbers, const std::string& extra = "") {
    json j = json::array();
    for (const double x : numbers) j.push_back(x);
    return j.dump() + extra;
}

std::map<std::string, Placed> NamedObjects(const EditsSpec& e) {
    std::map<std::string, Placed> out;
    for (const AddedBox& b : e.boxes) {
        out[b.name] = {"box", ShapeText({b.size.x(), b.size.y(), b.size.z()}), b.center, b.yaw_deg};
    }
    for (const AddedCylinder& c : e.cylinders) {
        out[c.name] = {"cylinder", ShapeText({c.radius_m, c.height_m}), c.base, 0.0};
    }
    for (const AddedMesh& m : e.meshes) {
        out[m.name] = {"mesh", ShapeText({m.scale}, m.file.string()), m.position, m.yaw_deg};
    }
    for (const AddedMirror& m : e.mirrors) {
        out[m.name] = {"mirror", ShapeText({m.size.x(), m.size.y()}), m.center, m.yaw_deg};
    }
    return out;
}

// changes.json's entries of `list` by key (an added object's name and kind, an element's
// GlobalId).
std::map<std::string, json> ByKey(const json& changes, const char* list, bool by_name) {
    std::map<std::string, json> out;
    if (!changes.contains(list)) return out;
    for (const json& e : changes[list]) {
        const std::string key =
            by_name ? e["kind"].get<std::string>() + "/" + e["name"].get<std::string>()
                    : e["global_id"].get<std::string>();
        out[key] = e;
    }
    return out;
}

// Adds the beam hits the visits' changes.json give an item: `beam_hits` (the later's) and
// `beam_hits_earlier`.
void AddHits(json& item, const json* earlier, const json* later) {
    if (later && later->contains("beam_hits")) item["beam_hits"] = (*later)["beam_hits"];
    if (earlier && earlier->contains("beam_hits")) {
        item["beam_hits_earlier"] = (*earlier)["beam_hits"];
    }
}

const json* Lookup(const std::map<std::string, json>& m, const std::string& key) {
    const auto it = m.find(key);
    return it == m.end() ? nullptr : &it->second;
}

bool SameObject(const Placed& a, const Placed& b) { return a.kind == b.kind && a.shape == b.shape; }

// An absent object's key in a HitWatch: by its place too, so that an object gone since two
// earlier visits where it stood in one place is cast once (two coincident copies would share its
// beams between them).
std::string AbsentKey(const std::string& name, const Placed& p) {
    return p.kind + "/" + name + " " + p.shape + " at " + Xyz(p.at).dump() + " yaw " +
           json(p.yaw_deg).dump();
}

json ObjectChanges(const VisitTruth& earlier, const VisitTruth& later) {
    const std::map<std::string, Placed> a = NamedObjects(earlier.scenario.edits);
    const std::map<std::string, Placed> b = NamedObjects(later.scenario.edits);
    const auto hits_a = ByKey(earlier.changes, "added", true);
    const auto hits_b = ByKey(later.changes, "added", true);
    json added = json::array(), gone = json::array(), moved = json::array(),
         unchanged = json::array();
    auto item = [&](const std::string& name, const Placed& p, bool in_earlier, bool in_later) {
        json j = {{"name", name}, {"kind", p.kind}};
        const std::string key = p.kind + "/" + name;
        AddHits(j, in_earlier ? Lookup(hits_a, key) : nullptr,
                in_later ? Lookup(hits_b, key) : nullptr);
        return j;
    };
    for (const auto& [name, p] : a) {
        const auto it = b.find(name);
        if (it == b.end() || !SameObject(it->second, p)) {
            json j = item(name, p, true, false);
            // The later walk's beams on where it stood (VisitWatch).
            const auto seen = later.watched_hits.find(AbsentKey(name, p));
            if (seen != later.watched_hits.end()) j["beam_hits"] = seen->second;
            gone.push_back(j);
            continue;
        }
        const Placed& q = it->second;
        const Eigen::Vector3d t = q.at - p.at;
        const double yaw = WrapYawDeg(q.yaw_deg - p.yaw_deg);
        json j = item(name, q, true, true);
        if (t.norm() > kMovedTranslationM || std::abs(yaw) > kMovedYawDeg) {
            j["translation"] = Xyz(t);
            j["yaw_deg"] = yaw;
            j["from"] = Xyz(p.at);
            j["to"] = Xyz(q.at);
            moved.push_back(j);
        } else {
            unchanged.push_back(j);
        }
    }
    for (const auto& [name, q] : b) {
        const auto it = a.find(name);
        if (it == a.end() || !SameObject(it->second, q))
            added.push_back(item(name, q, false, true));
    }
    return {{"new", added}, {"gone", gone}, {"moved", moved}, {"unchanged", unchanged}};
}

json ElementOf(const json& entry) {
    return {{"global_id", entry["global_id"]}, {"class", entry["class"]}, {"name", entry["name"]}};
}

// An element's placement in a visit: its translation and yaw when moved (reason "moved"), zero
// at its modelled place.
std::pair<Eigen::Vector3d, double> Placement(const json* moved) {
    if (!moved || (*moved)["reason"] != "moved") return {Eigen::Vector3d::Zero(), 0.0};
    const json& t = (*moved)["translation"];
    return {Eigen::Vector3d(t[0].get<double>(), t[1].get<double>(), t[2].get<double>()),
            (*moved)["yaw_deg"].get<double>()};
}

// The later walk's hits on an element that is no change of the later visit (VisitWatch).
void AddWatchedHits(json& j, const VisitTruth& later, const std::string& id) {
    const auto seen = later.watched_hits.find(id);
    if (seen != later.watched_hits.end()) j["beam_hits"] = seen->second;
}

json ElementChanges(const VisitTruth& earlier, const VisitTruth& later) {
    const auto removed_a = ByKey(earlier.changes, "removed", false);
    const auto removed_b = ByKey(later.changes, "removed", false);
    const auto moved_a = ByKey(earlier.changes, "moved", false);
    const auto moved_b = ByKey(later.changes, "moved", false);
    json newly_removed = json::array(), rebuilt = json::array(), newly_moved = json::array();
    for (const auto& [id, e] : removed_b) {
        if (removed_a.count(id)) continue;
        json j = ElementOf(e);
        AddHits(j, nullptr, &e);
        newly_removed.push_back(j);
    }
    for (const auto& [id, e] : removed_a) {
        if (removed_b.count(id)) continue;
        json j = ElementOf(e);
        AddHits(j, &e, Lookup(moved_b, id));
        if (!j.contains("beam_hits")) AddWatchedHits(j, later, id);
        rebuilt.push_back(j);
    }
    // Every element moved in either visit (and present in both): placed differently?
    std::map<std::string, json> either = moved_a;
    either.insert(moved_b.begin(), moved_b.end());
    for (const auto& [id, e] : either) {
        if (removed_a.count(id) || removed_b.count(id)) continue;
        const json* a = Lookup(moved_a, id);
        const json* b = Lookup(moved_b, id);
        const auto [ta, ya] = Placement(a);
        const auto [tb, yb] = Placement(b);
        const double yaw = WrapYawDeg(yb - ya);
        if ((tb - ta).norm() <= kMovedTranslationM && std::abs(yaw) <= kMovedYawDeg) continue;
        json j = ElementOf(e);
        j["translation"] = Xyz(tb - ta);
        j["yaw_deg"] = yaw;
        j["at_model_place"] = b == nullptr || (*b)["reason"] != "moved";
        AddHits(j, a, b);
        if (!j.contains("beam_hits")) AddWatchedHits(j, later, id);
        newly_moved.push_back(j);
    }
    return {{"newly_removed", newly_removed}, {"rebuilt", rebuilt}, {"newly_moved", newly_moved}};
}

json ReadJsonFile(const std::filesystem::path& file) {
    return json::parse(io::ReadFileToString(file));
}

}  // namespace

std::vector<size_t> VisitsByDate(const Scenario& s) {
    std::vector<size_t> order(s.visits.size());
    std::iota(order.begin(), order.end(), size_t{0});
    std::vector<int64_t> ns(order.size());
    for (size_t i = 0; i < order.size(); ++i) ns[i] = common::ParseUtcTime(s.visits[i].date);
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return ns[a] < ns[b]; });
    return order;
}

HitWatch VisitWatch(const std::vector<VisitTruth>& earlier, const Scenario& later) {
    HitWatch watch;
    const std::map<std::string, Placed> now = NamedObjects(later.edits);
    for (const VisitTruth& v : earlier) {
        const std::map<std::string, common::TriangleMesh> meshes =
            NamedObjectMeshes(v.scenario.edits);
        for (const auto& [name, p] : NamedObjects(v.scenario.edits)) {
            const auto it = now.find(name);
            if (it != now.end() && SameObject(it->second, p)) continue;
            watch.absent[AbsentKey(name, p)] = meshes.at(p.kind + "/" + name);
        }
        for (const char* list : {"removed", "moved"}) {
            for (const json& e : v.changes[list]) watch.elements.push_back(e["global_id"]);
        }
    }
    std::sort(watch.elements.begin(), watch.elements.end());
    watch.elements.erase(std::unique(watch.elements.begin(), watch.elements.end()),
                         watch.elements.end());
    return watch;
}

json VisitPairTruth(const VisitTruth& earlier, const VisitTruth& later) {
    return {{"earlier", earlier.label},
            {"later", later.label},
            {"objects", ObjectChanges(earlier, later)},
            {"elements", ElementChanges(earlier, later)}};
}

std::vector<VisitCapture> SimulateVisits(const Scenario& s, const bim::BimModel& model,
                                         const std::string& model_sha256,
                                         const std::filesystem::path& dir,
                                         const std::function<void(double)>& progress) {
    s.Validate();
    if (s.visits.empty()) {
        throw common::Error(common::StatusCode::kInvalidArgument, "the scenario has no visits");
    }
    const std::vector<size_t> order = VisitsByDate(s);
    std::vector<VisitCapture> out;
    std::vector<VisitTruth> truth;
    json visits = json::array(), pairs = json::array();
    for (size_t k = 0; k < order.size(); ++k) {
        const VisitSpec& v = s.visits[order[k]];
        VisitTruth t{v.label, VisitScenario(s, order[k]), json(), {}};
        const auto part = [&](double f) {
            if (progress) progress((double(k) + f) / double(order.size()));
        };
        try {
            out.push_back({v.label, v.date,
                           SimulateCapture(t.scenario, model, model_sha256, dir / v.label, part,
                                           VisitWatch(truth, t.scenario))});
        } catch (const common::FileError&) {
            throw;
        } catch (const common::Error& e) {
            throw common::Error(e.code(), "visit '" + v.label + "': " + e.what());
        }
        t.changes = ReadJsonFile(dir / v.label / "changes.json");
        t.watched_hits = out.back().report.watched_hits;
        visits.push_back({{"label", v.label},
                          {"date", common::FormatUtcTime(CaptureStartNs(t.scenario))},
                          {"start_ns", CaptureStartNs(t.scenario)},
                          {"folder", v.label},
                          {"platform", ToString(t.scenario.platform)}});
        for (size_t j = 0; j < truth.size(); ++j) {
            json pair = VisitPairTruth(truth[j], t);
            pair["consecutive"] = j + 1 == k;
            pairs.push_back(pair);
        }
        truth.push_back(std::move(t));
    }
    const json doc = {
        {"format", "bimslam-visits"},
        {"version", 1},
        {"frame", "bim"},
        {"moved_beyond", {{"translation_m", kMovedTranslationM}, {"yaw_deg", kMovedYawDeg}}},
        {"visits", visits},
        {"pairs", pairs}};
    io::WriteFileAtomic(dir / "visits.json", doc.dump(2) + "\n");
    return out;
}

}  // namespace bimslam::simulate
