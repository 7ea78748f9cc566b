// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/report/report_data.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <system_error>
#include <unordered_set>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/ply.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/io/trajectory.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/evaluation/trajectory_metrics.hpp"
#include "host_tools/report/report_deviation.hpp"
#include "host_tools/report/report_geometry.hpp"
#include "host_tools/report/report_visits.hpp"

namespace bimslam::report {
namespace fs = std::filesystem;
using nlohmann::json;

void ReportConfig::Validate() const {
    auto bad = [](const std::string& w) {
        throw common::Error(common::StatusCode::kInvalidArgument, w);
    };
    if (max_map_points < 1000) bad("max_map_points " + std::to_string(max_map_points) + " < 1000");
    if (!(plan_cut_height_m > 0 && plan_cut_height_m < 3)) bad("plan_cut_height_m out of (0, 3)");
    if (max_trajectory_points < 10) bad("max_trajectory_points < 10");
}

namespace {

// A new object's room in the page: the space's LongName ("Open office") when the file has one,
// else its Name; "" outside every space, and beyond the model's walls what it is: an annex or a
// shed the model lacks, or what stands around the building. changes.json before stop 49 has no
// long_name, before stop 63 no outside_footprint.
json RoomName(const json& object) {
    const json& space = object.at("space");
    if (space.is_null()) {
        return object.value("outside_footprint", false) ? "outside the model's footprint" : "";
    }
    const std::string long_name = space.value("long_name", "");
    return long_name.empty() ? space.at("name") : json(long_name);
}

bool Exists(const fs::path& p) {
    std::error_code ec;
    return fs::exists(p, ec);
}

json ReadJson(const fs::path& file) {
    try {
        return json::parse(io::ReadFileToString(file));
    } catch (const json::exception& e) {
        throw common::FileError(common::StatusCode::kParseError, file.string(), 0, e.what());
    }
}

std::vector<Eigen::Vector3d> Positions(const std::vector<io::StampedPose>& poses) {
    std::vector<Eigen::Vector3d> p;
    for (const auto& s : poses) p.push_back(s.translation);
    return p;
}

// APE over time, no alignment: the anchored trajectory against the truth, as `bimslam evaluate
// --align none` pairs them (evaluation::Associate).
json ApeOverTime(const fs::path& est_file, const fs::path& ref_file) {
    const auto est = io::ReadTum(est_file);
    const auto ref = io::ReadTum(ref_file);
    const auto pairs = evaluation::Associate(est, ref);
    json t = json::array(), e = json::array();
    const size_t step = std::max<size_t>(1, pairs.size() / 2000);
    for (size_t i = 0; i < pairs.size(); i += step) {
        const auto& a = est[pairs[i].est];
        const auto& b = ref[pairs[i].ref];
        t.push_back(double(a.stamp_ns - est.front().stamp_ns) * 1e-9);
        e.push_back((a.translation - b.translation).norm());
    }
    return {{"t", t}, {"e", e}};
}

// The map of a session that was not anchored, in its own (odometry) frame: keyframe clouds at
// their poses, one point per 10 cm voxel, at most max_points.
json OwnFrameMap(const fs::path& session_dir, size_t max_points) {
    const io::Session s = io::ReadSession(session_dir);
    std::vector<float> xyz;
    std::unordered_set<uint64_t> voxels;
    for (const io::SessionKeyframe& k : s.keyframes) {
        for (size_t i = 0; i < k.cloud.size(); ++i) {
            const Eigen::Vector3d p = k.T_world_lidar * k.cloud.xyz[i].cast<double>();
            const auto key = [](double v) {
                return uint64_t(int64_t(std::floor(v / 0.1)) & 0x1FFFFF);
            };
            if (!voxels.insert(key(p.x()) | key(p.y()) << 21 | key(p.z()) << 42).second) continue;
            xyz.insert(xyz.end(), {float(p.x()), float(p.y()), float(p.z())});
            if (xyz.size() / 3 >= max_points) break;
        }
    }
    return {{"points", Base64(xyz)},
            {"shown", xyz.size() / 3},
            {"trajectory", ThinPoints(Positions(s.trajectory), Eigen::Vector3d::Zero(), 4000)}};
}

std::vector<Eigen::Vector3d> Translations(const std::vector<Eigen::Isometry3d>& poses) {
    std::vector<Eigen::Vector3d> p;
    for (const auto& T : poses) p.push_back(T.translation());
    return p;
}

// A session's map coloured by distance (map_bim.ply), decimated to at most max_points, storey by
// storey for the 3D view's storey filter (storeys: [first point, count] per storey), added to
// `map` ({sessions, total, shown}).
void AddSessionMap(const fs::path& file, const std::string& name, const bim::BimModel& model,
                   size_t max_points, json& map, DistanceHistogram* histogram) {
    const io::PlyData ply = io::ReadPly(file);
    const io::PlyProperty* d = ply.Find("scalar_distance");
    const io::PlyProperty* cls = ply.Find("scalar_class");
    // Every point on the model (not only those shown), on the storey the 3D view puts it on.
    for (size_t i = 0; d && cls && i < ply.vertices.size(); ++i) {
        const double z = double(ply.vertices[i].z()) - model.origin_m.z();
        histogram->Add(StoreyOfPoint(model, z), float(d->values[i]), int(cls->values[i]));
    }
    const size_t step = std::max<size_t>(1, (ply.vertices.size() + max_points - 1) / max_points);
    const Eigen::Vector3f origin = model.origin_m.cast<float>();
    std::vector<std::vector<float>> xyz(std::max<size_t>(1, model.storeys.size())),
        dist(xyz.size());
    for (size_t i = 0; i < ply.vertices.size(); i += step) {
        const Eigen::Vector3f p = ply.vertices[i] - origin;
        const size_t k = size_t(std::max(0, StoreyOfPoint(model, p.z())));
        xyz[k].insert(xyz[k].end(), {p.x(), p.y(), p.z()});
        dist[k].push_back(d ? float(d->values[i]) : 0.0f);
    }
    std::vector<float> all_xyz, all_dist;
    json ranges = json::array();
    for (size_t k = 0; k < xyz.size(); ++k) {
        ranges.push_back({all_dist.size(), dist[k].size()});
        all_xyz.insert(all_xyz.end(), xyz[k].begin(), xyz[k].end());
        all_dist.insert(all_dist.end(), dist[k].begin(), dist[k].end());
    }
    map["sessions"].push_back({{"name", name},
                               {"points", Base64(all_xyz)},
                               {"distance", Base64(all_dist)},
                               {"storeys", ranges}});
    map["total"] = map["total"].get<size_t>() + ply.vertices.size();
    map["shown"] = map["shown"].get<size_t>() + all_dist.size();
}

// A session's new objects' voxel meshes (new_objects.ply) for the 3D view, their triangles
// storey by storey (each object's storey in changes.json; storeys: [first index, count] per
// storey), so that the storey filter draws one storey's as a range.
json ObjectMeshes(const fs::path& file, const std::string& name, const json& changes,
                  const bim::BimModel& model) {
    const io::PlyData ply = io::ReadPly(file);
    std::map<int32_t, int> storey_of;  // object id -> storey
    for (const json& o : changes.at("new_objects")) {
        const json& s = o.value("storey", json(nullptr));
        storey_of[o.at("id").get<int32_t>()] = s.is_object() ? s.value("index", 0) : 0;
    }
    std::vector<float> xyz;
    std::vector<uint8_t> rgb;
    std::vector<int32_t> obj;
    const auto* red = ply.Find("red");
    const auto* green = ply.Find("green");
    const auto* blue = ply.Find("blue");
    const auto* object = ply.Find("object");
    for (size_t i = 0; i < ply.vertices.size(); ++i) {
        const Eigen::Vector3f p = ply.vertices[i] - model.origin_m.cast<float>();
        xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
        rgb.insert(rgb.end(),
                   {uint8_t(red ? red->values[i] : 200), uint8_t(green ? green->values[i] : 120),
                    uint8_t(blue ? blue->values[i] : 0)});
        obj.push_back(object ? int32_t(object->values[i]) : -1);
    }
    const auto storey = [&](const auto& t) {
        const auto it = storey_of.find(obj[t[0]]);
        return it == storey_of.end() ? 0 : std::max(0, it->second);
    };
    std::vector<std::vector<uint32_t>> by_storey(std::max<size_t>(1, model.storeys.size()));
    for (const auto& t : ply.triangles) {
        auto& idx = by_storey[std::min(by_storey.size() - 1, size_t(storey(t)))];
        idx.insert(idx.end(), t.begin(), t.end());
    }
    std::vector<uint32_t> idx;
    json ranges = json::array();
    for (const std::vector<uint32_t>& part : by_storey) {
        ranges.push_back({idx.size(), part.size()});
        idx.insert(idx.end(), part.begin(), part.end());
    }
    return {{"session", name},        {"positions", Base64(xyz)}, {"colors", Base64(rgb)},
            {"indices", Base64(idx)}, {"object", Base64(obj)},    {"storeys", ranges}};
}

// A storey in changes.json: a name, an object with a name, or null.
json StoreyName(const json& e) {
    const json s = e.value("storey", json(nullptr));
    if (s.is_string()) return s;
    if (s.is_object()) return s.value("name", json(""));
    return "";
}

}  // namespace

namespace {

// The model's part of the page: its origin, bounds, plans, flights and 3D buffers.
void AddModel(const bim::BimModel& model, const fs::path& model_file, const ReportConfig& config,
              const ReportProgress& progress, json& data) {
    const Eigen::Vector3d origin = model.origin_m;
    data["origin"] = {origin.x(), origin.y(), origin.z()};
    const Eigen::AlignedBox3d box = model.Bounds();
    data["bounds"] = {
        {"min",
         {box.min().x() - origin.x(), box.min().y() - origin.y(), box.min().z() - origin.z()}},
        {"max",
         {box.max().x() - origin.x(), box.max().y() - origin.y(), box.max().z() - origin.z()}}};
    data["model"] = {{"file", model_file.string()},
                     {"schema", model.schema},
                     {"elements", model.elements.size()},
                     {"triangles", model.mesh.triangles.size()}};
    progress("floor plans", 0.2);
    data["storeys"] = PlanSections(model, config.plan_cut_height_m);
    data["flights"] = FlightOutlines(model);
    progress("model buffers", 0.3);
    data["model3d"] = ModelBuffers(model);
}

using KeyframesBySession = std::map<std::string, std::vector<Eigen::Isometry3d>>;

// One recording of the visit: its trajectory, storey runs and APE when anchored (its keyframes
// into `keyframes`), its own-frame map when not, its scan times.
json SessionJson(const json& rec, const fs::path& visit, const bim::BimModel& model,
                 const ReportConfig& config, KeyframesBySession& keyframes) {
    const std::string name = rec.at("name");
    // Anchored in parts: the anchored pieces' keyframes and scans are in OUT/anchor/NAME.
    const bool anchored =
        !rec.at("anchor").is_null() &&
        (rec["anchor"]["verdict"] == "anchored" || rec["anchor"]["verdict"] == "anchored-in-parts");
    json s = {{"name", name}, {"anchored", anchored}, {"anchor", rec.at("anchor")}};
    const fs::path anchored_dir = visit / "anchor" / name;
    if (anchored) {
        keyframes[name] = io::ReadKitti(anchored_dir / "optimized_poses.txt");
        const std::vector<Eigen::Vector3d> trajectory =
            Positions(io::ReadTum(anchored_dir / "trajectory_bim.tum"));
        s["trajectory"] = ThinPoints(trajectory, model.origin_m, config.max_trajectory_points);
        s["runs"] = StoreyRuns(trajectory, model, config.max_trajectory_points);
        if (rec.at("ground_truth").is_string()) {
            s["ape"] = ApeOverTime(anchored_dir / "trajectory_bim.tum",
                                   rec["ground_truth"].get<std::string>());
        }
    } else if (Exists(visit / "odometry" / name / "session.json")) {
        s["own_frame"] = OwnFrameMap(visit / "odometry" / name, config.max_map_points / 4);
    }
    const fs::path odo = visit / "odometry" / (name + ".json");
    if (Exists(odo)) {
        const json o = ReadJson(odo);
        s["scan_ms"] = o.at("scan_ms");
    }
    return s;
}

// A missing or deviating element's row of the change list (its box from the model).
json ElementRow(const bim::BimModel& model, const json& e, const std::string& kind,
                const std::string& session) {
    const size_t index = e.at("index");
    const Eigen::AlignedBox3d b = ElementBox(model, index);
    const Eigen::Vector3d lo = b.min(), hi = b.max();
    const Eigen::Vector3d size = hi - lo, mid = (lo + hi) / 2;
    std::string verdict = kind;
    if (kind == "deviating") {
        verdict +=
            e.at("moved").is_null()
                ? " by " +
                      std::to_string(int(std::round(e.at("offset_norm_m").get<double>() * 1000))) +
                      " mm"
                : " (moved)";
    }
    return {
        {"kind", kind},
        {"session", session},
        {"id", index},
        {"name", e.at("name").get<std::string>() + " (" + e.at("class").get<std::string>() + ")"},
        {"global_id", e.at("global_id")},
        {"min", {lo.x(), lo.y(), lo.z()}},
        {"max", {hi.x(), hi.y(), hi.z()}},
        {"size", {size.x(), size.y(), size.z()}},
        {"position", {mid.x(), mid.y(), mid.z()}},
        {"storey", StoreyName(e)},
        {"room", ""},
        {"verdict", verdict}};
}

// What the visit's recordings found, gathered over them: the change list's rows, the missing
// elements, the maps coloured by distance, the new objects' meshes, the distances' histogram.
struct VisitChanges {
    json rows = json::array();
    std::vector<size_t> missing_elements;
    json map = nullptr, objects = json::array();
    std::vector<fs::path> dirs;                  // the elements' deviations (elements.csv)
    std::optional<DistanceHistogram> distances;  // of the maps' points on the model

    // One recording's changes folder `cdir` (its changes.json read as `c`).
    void Add(const fs::path& cdir, const std::string& name, const json& c,
             const bim::BimModel& model, const ReportConfig& config) {
        dirs.push_back(cdir);
        for (const json& o : c.at("new_objects")) {
            rows.push_back({{"kind", "new object"},
                            {"session", name},
                            {"id", o.at("id")},
                            {"name", "new object " + std::to_string(o.at("id").get<int>())},
                            {"min", o.at("box_min")},
                            {"max", o.at("box_max")},
                            {"size", o.at("size_m")},
                            {"position", o.at("centroid")},
                            {"storey", StoreyName(o)},
                            {"room", RoomName(o)},
                            {"verdict", "new"},
                            {"color", o.at("color")}});
        }
        for (const char* kind : {"missing", "deviating"}) {
            for (const json& e : c.at(kind)) {
                rows.push_back(ElementRow(model, e, kind, name));
                if (std::string(kind) == "missing") missing_elements.push_back(e.at("index"));
            }
        }
        // The map coloured by distance and the new objects' meshes (the first anchored session's
        // map, or each, thinned together).
        if (Exists(cdir / "map_bim.ply")) {
            if (map.is_null()) map = {{"sessions", json::array()}, {"total", 0}, {"shown", 0}};
            if (!distances) {  // the model's points are within the new-object threshold of it
                const double range = c.at("parameters").value("new_object_threshold_m", 0.10);
                distances.emplace(model.storeys.size(), range, 0.005);
            }
            AddSessionMap(cdir / "map_bim.ply", name, model, config.max_map_points, map,
                          &*distances);
        }
        if (Exists(cdir / "new_objects.ply")) {
            objects.push_back(ObjectMeshes(cdir / "new_objects.ply", name, c, model));
        }
    }
};

// Loops: from the target keyframe to where registration put the query keyframe
// (T_world_target * T_target_query), accepted or rejected.
json LoopRows(const json& loops, const KeyframesBySession& keyframes,
              const Eigen::Vector3d& origin) {
    json loop_rows = json::array();
    for (const json& l : loops) {
        const auto it = keyframes.find(l.at("target").get<std::string>());
        const size_t ti = l.at("target_index");
        if (it == keyframes.end() || ti >= it->second.size()) continue;
        const Eigen::Isometry3d& T_world_target = it->second[ti];
        const auto& c = l.at("T_target_query");  // x y z qx qy qz qw
        Eigen::Isometry3d T_target_query = Eigen::Isometry3d::Identity();
        T_target_query.linear() = Eigen::Quaterniond(c[6].get<double>(), c[3].get<double>(),
                                                     c[4].get<double>(), c[5].get<double>())
                                      .normalized()
                                      .toRotationMatrix();
        T_target_query.translation() =
            Eigen::Vector3d(c[0].get<double>(), c[1].get<double>(), c[2].get<double>());
        const Eigen::Vector3d target = T_world_target.translation();
        const Eigen::Vector3d query = (T_world_target * T_target_query).translation();
        loop_rows.push_back({{"query", l.at("query")},
                             {"accepted", l.at("accepted")},
                             {"source", l.at("source")},
                             {"inlier_ratio", l.at("inlier_ratio")},
                             {"inlier_rmse_m", l.at("inlier_rmse_m")},
                             {"reason", l.at("reason")},
                             {"a", ThinPoints({target}, origin, 1)},
                             {"b", ThinPoints({query}, origin, 1)}});
    }
    return loop_rows;
}

}  // namespace

json CollectReportData(const fs::path& out, const ReportConfig& config,
                       const ReportProgress& progress_in) {
    config.Validate();
    const ReportProgress progress = progress_in ? progress_in : [](const std::string&, double) {};
    const fs::path summary_file = out / "summary.json";
    if (!Exists(summary_file)) {
        throw common::FileError(common::StatusCode::kNotFound, out.string(), 0,
                                "not an output of `bimslam map`: no summary.json");
    }
    json data;
    data["summary"] = ReadJson(summary_file);
    const json& summary = data["summary"];
    const fs::path model_file = summary.at("model").at("file").get<std::string>();

    progress("reading the model", 0.0);
    const bim::BimModel model = bim::LoadIfc(model_file);
    AddModel(model, model_file, config, progress, data);

    // The reference walk (its keyframes, world frame = bim).
    KeyframesBySession keyframes;  // world poses by session
    if (Exists(out / "reference" / "optimized_poses.txt")) {
        keyframes["reference"] = io::ReadKitti(out / "reference" / "optimized_poses.txt");
        data["reference_runs"] =
            StoreyRuns(Translations(keyframes["reference"]), model, config.max_trajectory_points);
    }

    // Per recording: trajectories, loops, APE, scan times, own-frame map when not anchored. The
    // recordings of the visit the summary describes (`bimslam map`'s newest: OUT/visits/<label>;
    // a summary without visit_dir, of an older bimslam: OUT itself).
    const fs::path visit = out / summary.value("visit_dir", std::string());
    const json loops = Exists(visit / "anchor" / "loops.json")
                           ? ReadJson(visit / "anchor" / "loops.json")
                           : json::array();
    json sessions = json::array();
    VisitChanges changes;
    const auto& recordings = summary.at("recordings");
    for (size_t r = 0; r < recordings.size(); ++r) {
        const std::string name = recordings[r].at("name");
        progress("session " + name, 0.4 + 0.5 * double(r) / double(recordings.size()));
        sessions.push_back(SessionJson(recordings[r], visit, model, config, keyframes));
        const fs::path cdir = visit / "changes" / name;
        if (Exists(cdir / "changes.json")) {
            changes.Add(cdir, name, ReadJson(cdir / "changes.json"), model, config);
        }
    }
    data["sessions"] = sessions;
    data["changes"] = changes.rows;
    data["map"] = changes.map;
    data["objects"] = changes.objects;
    data["missing3d"] = ElementTriangles(model, changes.missing_elements);
    data["deviation"] = ElementDeviations(changes.dirs);
    data["distances"] = changes.distances ? changes.distances->ToJson(model) : json(nullptr);
    data["loops"] = LoopRows(loops, keyframes, model.origin_m);
    // The project's visits and history (issue 33 item 6; none from an older bimslam).
    progress("visits and history", 0.95);
    data["visits"] = VisitWalks(out, summary, model, config.max_trajectory_points);
    data["history"] = HistoryForPage(out, model);
    data["config"] = {{"max_map_points", config.max_map_points},
                      {"plan_cut_height_m", config.plan_cut_height_m}};
    progress("done", 1.0);
    return data;
}

}  // namespace bimslam::report
