// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/changes/change_evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/ply.hpp"
#include "algorithms/simulation/scene.hpp"

namespace bimslam::change_detection {
namespace {
using nlohmann::json;

[[noreturn]] void Bad(const std::filesystem::path& file, const std::string& what) {
    throw common::FileError(common::StatusCode::kParseError, file.string(), 0, what);
}

json ParseJson(const std::filesystem::path& file) {
    try {
        return json::parse(io::ReadFileToString(file));
    } catch (const json::exception& e) {
        Bad(file, std::string("not JSON: ") + e.what());
    }
}

Eigen::Vector3d Vec3(const std::filesystem::path& file, const json& j, const std::string& field) {
    if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() ||
        !j[2].is_number()) {
        Bad(file, field + ": expected 3 numbers");
    }
    return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

// The fields of one CSV line (RFC 4180 quoting).
std::vector<std::string> CsvFields(std::string_view line) {
    std::vector<std::string> out(1);
    bool quoted = false;
    for (size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (quoted) {
            if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
                out.back() += '"';
                ++i;
            } else if (c == '"') {
                quoted = false;
            } else {
                out.back() += c;
            }
        } else if (c == '"') {
            quoted = true;
        } else if (c == ',') {
            out.emplace_back();
        } else if (c != '\r') {
            out.back() += c;
        }
    }
    return out;
}

double IoU(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b) {
    const Eigen::AlignedBox3d i = a.intersection(b);
    if (i.isEmpty()) return 0;
    const double vi = i.volume();
    return vi / (a.volume() + b.volume() - vi);
}

double DistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                         const Eigen::Vector2d& b) {
    const Eigen::Vector2d d = b - a;
    const double f =
        d.squaredNorm() > 0 ? std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0;
    return (a + f * d - p).norm();
}

json Scores(const DetectionScores& s) {
    return {{"truth", s.truth},
            {"found", s.found},
            {"truth_matched", s.truth_matched},
            {"found_matched", s.found_matched},
            {"precision", s.precision()},
            {"recall", s.recall()},
            {"f1", s.f1()}};
}

// map_bim.ply's points, their distance to the model and keyframe counts (change_report.hpp).
void ReadMap(const std::filesystem::path& file, FoundChanges* f) {
    if (!std::filesystem::exists(file)) return;
    const io::PlyData ply = io::ReadPly(file);
    const io::PlyProperty* distance = ply.Find("scalar_distance");
    const io::PlyProperty* keyframes = ply.Find("scalar_keyframes");
    if (!distance || !keyframes) Bad(file, "no scalar_distance or scalar_keyframes property");
    const io::PlyProperty* cls = ply.Find("scalar_class");
    const io::PlyProperty* element = ply.Find("scalar_element");
    f->map.resize(ply.vertices.size());
    for (size_t i = 0; i < ply.vertices.size(); ++i) {
        f->map[i] = {ply.vertices[i], std::abs(float(distance->values[i])),
                     uint32_t(std::max(0.0, keyframes->values[i])),
                     cls ? uint8_t(cls->values[i]) : uint8_t(255),
                     element ? int32_t(element->values[i]) : -1};
    }
    f->has_map = true;
}

}  // namespace

TruthChanges ReadTruthChanges(const std::filesystem::path& file) {
    const json j = ParseJson(file);
    TruthChanges t;
    try {
        for (const json& a : j.at("added")) {
            TruthChanges::Added added{
                a.at("name").get<std::string>(),
                a.at("kind").get<std::string>(),
                Eigen::AlignedBox3d(Vec3(file, a.at("box_min"), "added.box_min"),
                                    Vec3(file, a.at("box_max"), "added.box_max")),
                {}};
            added.beam_hits = a.value("beam_hits", -1L);
            if (a.contains("mesh")) {
                added.mesh = io::MeshFromPly(
                    io::ReadPly(file.parent_path() / a.at("mesh").get<std::string>()));
            }
            t.added.push_back(std::move(added));
        }
        for (const json& r : j.at("removed")) {
            t.removed.push_back(r.at("global_id").get<std::string>());
            if (r.contains("beam_hits")) {
                t.removed_beam_hits[t.removed.back()] = r.at("beam_hits").get<long>();
            }
        }
        for (const json& m : j.at("moved")) {
            TruthChanges::Moved mv;
            mv.global_id = m.at("global_id").get<std::string>();
            mv.ifc_class = m.value("class", "");
            mv.name = m.value("name", "");
            mv.reason = m.at("reason").get<std::string>();
            mv.translation = Vec3(file, m.at("translation"), "moved.translation");
            mv.yaw_deg = m.value("yaw_deg", 0.0);
            t.moved.push_back(mv);
        }
        for (const json& p : j.at("people")) {
            TruthChanges::Person person;
            person.from = {p.at("from").at(0).get<double>(), p.at("from").at(1).get<double>()};
            person.to = {p.at("to").at(0).get<double>(), p.at("to").at(1).get<double>()};
            person.radius_m = p.at("radius_m").get<double>();
            person.height_m = p.at("height_m").get<double>();
            person.floor_z = p.value("floor_z", 0.0);
            t.people.push_back(person);
        }
    } catch (const json::exception& e) {
        Bad(file,
            std::string("not a changes truth file (added, removed, moved, people): ") + e.what());
    }
    return t;
}

FoundChanges ReadFoundChanges(const std::filesystem::path& dir) {
    const std::filesystem::path file = dir / "changes.json";
    const json j = ParseJson(file);
    FoundChanges f;
    try {
        if (j.at("format") != "bimslam-changes") Bad(file, "format is not bimslam-changes");
        for (const json& o : j.at("new_objects")) {
            FoundChanges::Object object{Eigen::AlignedBox3d(Vec3(file, o.at("box_min"), "box_min"),
                                                            Vec3(file, o.at("box_max"), "box_max")),
                                        o.value("ifc_global_id", ""), "", o.value("id", -1),
                                        o.value("volume_m3", 0.0)};
            if (o.contains("storey") && o.at("storey").is_object())
                object.storey = o.at("storey").value("name", "");
            if (o.contains("plan_size_m")) {
                const json& plan = o.at("plan_size_m");
                if (!plan.is_array() || plan.size() != 2 || !plan[0].is_number() ||
                    !plan[1].is_number() || !(plan[0].get<double>() >= plan[1].get<double>()) ||
                    !(plan[1].get<double>() >= 0)) {
                    Bad(file, "plan_size_m must be [long, short] in metres, long >= short >= 0");
                }
                object.plan_long_m = plan[0].get<double>();
                object.plan_short_m = plan[1].get<double>();
            }
            if (o.contains("plan_center_m")) {
                const json& c = o.at("plan_center_m");
                if (!c.is_array() || c.size() != 2 || !c[0].is_number() || !c[1].is_number() ||
                    !std::isfinite(c[0].get<double>()) || !std::isfinite(c[1].get<double>())) {
                    Bad(file, "plan_center_m must be [x, y] in metres");
                }
                object.plan_center = Eigen::Vector2d(c[0].get<double>(), c[1].get<double>());
            }
            f.objects.push_back(std::move(object));
        }
        for (const json& t : j.at("transients")) {
            f.transients.push_back(Vec3(file, t.at("centroid"), "transients.centroid"));
        }
        const json& parameters = j.at("parameters");
        f.min_object_points = parameters.value("min_object_points", f.min_object_points);
        f.band_threshold_m = parameters.value("band_threshold_m", f.band_threshold_m);
        f.min_multi_view_fraction =
            parameters.value("min_multi_view_fraction", f.min_multi_view_fraction);
        if (parameters.contains("elements")) {
            f.min_judged_area_m2 =
                parameters.at("elements").value("min_judged_area_m2", f.min_judged_area_m2);
        }
        // Files written before the datum existed have none.
        const json& refinement = parameters.at("refinement");
        if (refinement.contains("datum")) {
            for (const json& d : refinement.at("datum")) {
                f.datum.insert(d.at("global_id").get<std::string>());
            }
        }
    } catch (const json::exception& e) {
        Bad(file, std::string("malformed: ") + e.what());
    }
    ReadMap(dir / "map_bim.ply", &f);
    const std::filesystem::path csv = dir / "elements.csv";
    const std::string text = io::ReadFileToString(csv);
    size_t line_start = 0, line_number = 0;
    std::map<std::string, size_t> column;
    while (line_start < text.size()) {
        size_t end = text.find('\n', line_start);
        if (end == std::string::npos) end = text.size();
        const std::vector<std::string> fields =
            CsvFields(std::string_view(text).substr(line_start, end - line_start));
        line_start = end + 1;
        ++line_number;
        if (line_number == 1) {
            for (size_t k = 0; k < fields.size(); ++k) column[fields[k]] = k;
            for (const char* need :
                 {"global_id", "verdict", "expected_area_m2", "support_points", "offset_x_m",
                  "offset_y_m", "offset_z_m", "moved", "moved_yaw_deg"}) {
                if (!column.count(need)) Bad(csv, std::string("no column ") + need);
            }
            continue;
        }
        if (fields.size() != column.size()) {
            throw common::FileError(common::StatusCode::kParseError, csv.string(), line_number,
                                    "expected " + std::to_string(column.size()) + " fields");
        }
        try {
            const auto get = [&](const char* name) { return fields[column.at(name)]; };
            FoundChanges::Element e;
            e.verdict = get("verdict");
            const auto optional = [&](const char* name) {
                return column.count(name) ? fields[column.at(name)] : std::string();
            };
            e.ifc_class = optional("class");
            e.name = optional("name");
            e.storey = optional("storey");
            if (column.count("index")) e.index = std::stoi(get("index"));
            e.expected_area_m2 = std::stod(get("expected_area_m2"));
            e.support_points = std::stoul(get("support_points"));
            e.offset = {std::stod(get("offset_x_m")), std::stod(get("offset_y_m")),
                        std::stod(get("offset_z_m"))};
            e.moved = get("moved") == "1";
            e.moved_yaw_deg = std::stod(get("moved_yaw_deg"));
            f.elements[get("global_id")] = e;
        } catch (const std::exception&) {
            throw common::FileError(common::StatusCode::kParseError, csv.string(), line_number,
                                    "a malformed number");
        }
    }
    return f;
}

namespace {

// Points on a mesh's surface, every `step` metres or closer (its vertices, edge points, and points
// inside its triangles on a barycentric grid).
std::vector<Eigen::Vector3f> SurfacePoints(const common::TriangleMesh& m, float step) {
    std::vector<Eigen::Vector3f> out;
    for (const auto& t : m.triangles) {
        const Eigen::Vector3f a = m.vertices[t[0]], b = m.vertices[t[1]], c = m.vertices[t[2]];
        const float longest = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()});
        const int n = std::max(1, int(std::ceil(longest / step)));
        for (int i = 0; i <= n; ++i) {
            for (int k = 0; k <= n - i; ++k) {
                out.push_back(a + (b - a) * (float(i) / float(n)) +
                              (c - a) * (float(k) / float(n)));
            }
        }
    }
    return out;
}

// Groups of true objects whose surfaces come within touch_m of each other (union-find).
std::vector<int> TouchingGroups(const TruthChanges& truth, double touch_m) {
    const size_t n = truth.added.size();
    std::vector<int> group(n);
    for (size_t i = 0; i < n; ++i) group[i] = int(i);
    const auto find = [&](int x) {
        while (group[size_t(x)] != x) x = group[size_t(x)] = group[size_t(group[size_t(x)])];
        return x;
    };
    for (size_t i = 0; i < n; ++i) {
        if (truth.added[i].mesh.empty()) continue;
        const simulation::Scene scene(truth.added[i].mesh);
        for (size_t j = i + 1; j < n; ++j) {
            if (truth.added[j].mesh.empty() ||
                truth.added[i].box.exteriorDistance(truth.added[j].box) > touch_m) {
                continue;
            }
            bool touch = false;
            for (const Eigen::Vector3f& p : SurfacePoints(truth.added[j].mesh, 0.02f)) {
                if (scene.ClosestPoint(p, float(touch_m))) {
                    touch = true;
                    break;
                }
            }
            if (touch) group[size_t(find(int(j)))] = find(int(i));
        }
    }
    for (size_t i = 0; i < n; ++i) group[i] = find(int(i));
    return group;
}

// Precision, recall (all and large) of found boxes against true boxes, matched one to one. A true
// object may also be matched by the part of it the walk saw (`seen`, parallel to `truth`; an empty
// box where there is none): the detector can only report what its map holds, and a bookcase seen
// from its door is its face, whose centre is 0.6 m from the whole bookcase's.
void ScoreBoxes(const std::vector<Eigen::AlignedBox3d>& truth,
                const std::vector<Eigen::AlignedBox3d>& seen,
                const std::vector<Eigen::AlignedBox3d>& found, const EvaluationConfig& config,
                DetectionScores* all, DetectionScores* large_only, std::vector<int>* found_match) {
    struct Pair {
        double iou, distance;
        size_t t, f;
    };
    std::vector<Pair> pairs;
    for (size_t t = 0; t < truth.size(); ++t) {
        for (size_t f = 0; f < found.size(); ++f) {
            double iou = IoU(truth[t], found[f]);
            double d = (truth[t].center() - found[f].center()).norm();
            if (t < seen.size() && !seen[t].isEmpty()) {
                iou = std::max(iou, IoU(seen[t], found[f]));
                d = std::min(d, (seen[t].center() - found[f].center()).norm());
            }
            if (iou >= config.min_iou || d <= config.max_centroid_m)
                pairs.push_back({iou, d, t, f});
        }
    }
    std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) {
        return a.iou != b.iou ? a.iou > b.iou : a.distance < b.distance;
    });
    std::vector<int> truth_match(truth.size(), -1);
    found_match->assign(found.size(), -1);
    for (const Pair& p : pairs) {
        if (truth_match[p.t] >= 0 || (*found_match)[p.f] >= 0) continue;
        truth_match[p.t] = int(p.f);
        (*found_match)[p.f] = int(p.t);
    }
    const auto large = [&](const Eigen::AlignedBox3d& b) {
        return b.sizes().maxCoeff() >= config.large_object_m;
    };
    for (size_t t = 0; t < truth.size(); ++t) {
        ++all->truth;
        all->truth_matched += truth_match[t] >= 0;
        if (large(truth[t])) {
            ++large_only->truth;
            large_only->truth_matched += truth_match[t] >= 0;
        }
    }
    for (size_t f = 0; f < found.size(); ++f) {
        ++all->found;
        all->found_matched += (*found_match)[f] >= 0;
        if (large(found[f])) {
            ++large_only->found;
            large_only->found_matched += (*found_match)[f] >= 0;
        }
    }
}

// Distance from p to the surface of a box (inside or out).
double BoxSurfaceDistance(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& p) {
    if (!box.contains(p)) return box.exteriorDistance(p);
    const Eigen::Vector3d below = p - box.min(), above = box.max() - p;
    return std::min(below.minCoeff(), above.minCoeff());
}

// The map points the keyframes put on a true object: within on_object_m of its surface (its mesh,
// else its box), nearer to it than to the model and farther than band_threshold_m from the model.
// Returns how many, how many of them two keyframes or more saw, and their box (the part seen).
struct OnObject {
    size_t points = 0, multi_view = 0;
    Eigen::AlignedBox3d box;  // empty: none
};
OnObject PointsOnObject(const TruthChanges::Added& a, const FoundChanges& found,
                        double on_object_m) {
    std::optional<simulation::Scene> scene;
    if (!a.mesh.empty()) scene.emplace(a.mesh);
    Eigen::AlignedBox3d reach = a.box;
    reach.min().array() -= on_object_m;
    reach.max().array() += on_object_m;
    OnObject on;
    for (const FoundChanges::MapPoint& m : found.map) {
        const Eigen::Vector3d p = m.xyz.cast<double>();
        if (!reach.contains(p) || m.model_distance_m <= found.band_threshold_m) continue;
        double d = 0;
        if (scene) {
            const auto c = scene->ClosestPoint(m.xyz, float(on_object_m));
            if (!c) continue;
            d = c->distance;
        } else {
            d = BoxSurfaceDistance(a.box, p);
            if (d > on_object_m) continue;
        }
        if (d >= m.model_distance_m) continue;
        ++on.points;
        on.multi_view += m.keyframes >= 2;
        on.box.extend(p);
    }
    return on;
}

// What the walk saw of each true added object (file comment of change_evaluation.hpp): its map
// points, whether it was in view and, if so, the box of the part seen.
std::vector<ChangeEvaluation::AddedView> AddedViews(const TruthChanges& truth,
                                                    const FoundChanges& found,
                                                    const EvaluationConfig& config) {
    std::vector<ChangeEvaluation::AddedView> views;
    for (const TruthChanges::Added& a : truth.added) {
        ChangeEvaluation::AddedView v;
        v.name = a.name;
        v.large = a.box.sizes().maxCoeff() >= config.large_object_m;
        v.beam_hits = a.beam_hits;
        v.in_view = true;
        if (found.has_map) {
            const OnObject on = PointsOnObject(a, found, config.on_object_m);
            v.map_points = on.points;
            v.multi_view_points = on.multi_view;
            v.in_view =
                v.map_points >= found.min_object_points &&
                double(v.multi_view_points) >= found.min_multi_view_fraction * double(v.map_points);
            if (v.in_view) v.seen_box = on.box;
        }
        views.push_back(v);
    }
    return views;
}

// The scores of what the walk saw: recall over the true objects in view (a true object counts as
// matched when a found one matched it); precision as for all of them.
void ScoreSeen(std::vector<ChangeEvaluation::AddedView> views, const FoundChanges& found,
               const std::vector<int>& found_match, const EvaluationConfig& config,
               ChangeEvaluation* ev) {
    ev->in_view_rule = {found.min_object_points, found.min_multi_view_fraction, config.on_object_m,
                        found.band_threshold_m, found.min_judged_area_m2};
    for (const int t : found_match) {
        if (t >= 0) views[size_t(t)].found = true;
    }
    ev->added_seen = ev->added;
    ev->added_seen_large = ev->added_large;
    ev->added_seen.truth = ev->added_seen.truth_matched = 0;
    ev->added_seen_large.truth = ev->added_seen_large.truth_matched = 0;
    for (const ChangeEvaluation::AddedView& v : views) {
        if (!v.in_view) {
            ++ev->added_out_of_view;
            ev->added_large_out_of_view += v.large;
            ev->added_no_beam += v.beam_hits == 0;
            ev->added_large_no_beam += v.large && v.beam_hits == 0;
            continue;
        }
        ++ev->added_seen.truth;
        ev->added_seen.truth_matched += v.found;
        if (v.large) {
            ++ev->added_seen_large.truth;
            ev->added_seen_large.truth_matched += v.found;
        }
    }
    ev->added_view = std::move(views);
}

}  // namespace

ChangeEvaluation EvaluateChanges(const TruthChanges& truth, const FoundChanges& found,
                                 const EvaluationConfig& config) {
    ChangeEvaluation ev;
    std::vector<Eigen::AlignedBox3d> truth_boxes, found_boxes;
    for (const auto& a : truth.added) truth_boxes.push_back(a.box);
    for (const auto& o : found.objects) found_boxes.push_back(o.box);
    std::vector<ChangeEvaluation::AddedView> views = AddedViews(truth, found, config);
    std::vector<Eigen::AlignedBox3d> seen_boxes;
    for (const auto& v : views) seen_boxes.push_back(v.seen_box);
    std::vector<int> found_match;
    ScoreBoxes(truth_boxes, seen_boxes, found_boxes, config, &ev.added, &ev.added_large,
               &found_match);
    ScoreSeen(std::move(views), found, found_match, config, &ev);
    // The same with touching true objects as one (and the parts of them seen, as one).
    const std::vector<int> group = TouchingGroups(truth, config.touch_m);
    std::map<int, Eigen::AlignedBox3d> union_box, union_seen;
    std::map<int, size_t> members;
    for (size_t i = 0; i < truth.added.size(); ++i) {
        union_box[group[i]].extend(truth.added[i].box);
        union_seen[group[i]].extend(seen_boxes[i]);
        ++members[group[i]];
    }
    std::vector<Eigen::AlignedBox3d> grouped, grouped_seen;
    for (const auto& [g, box] : union_box) {
        grouped.push_back(box);
        grouped_seen.push_back(union_seen[g]);
        ev.touching_groups += members[g] > 1;
    }
    std::vector<int> grouped_match;
    ScoreBoxes(grouped, grouped_seen, found_boxes, config, &ev.added_separable,
               &ev.added_separable_large, &grouped_match);

    // Removed elements.
    const auto expected_area = [&](const std::string& id) {
        const auto it = found.elements.find(id);
        return it == found.elements.end() ? 0.0 : it->second.expected_area_m2;
    };
    for (const std::string& id : truth.removed) {
        const auto it = found.elements.find(id);
        const bool hit = it != found.elements.end() && it->second.verdict == "missing";
        ++ev.removed.truth;
        ev.removed.truth_matched += hit;
        ChangeEvaluation::RemovedView v;
        v.global_id = id;
        v.found = hit;
        v.expected_area_m2 = expected_area(id);
        v.in_view = !found.has_map || v.expected_area_m2 >= found.min_judged_area_m2;
        const auto beams = truth.removed_beam_hits.find(id);
        if (beams != truth.removed_beam_hits.end()) v.beam_hits = beams->second;
        ev.removed_view.push_back(v);
        if (!v.in_view) {
            ++ev.removed_out_of_view;
            ev.removed_no_beam += v.beam_hits == 0;
        } else {
            ++ev.removed_seen.truth;
            ev.removed_seen.truth_matched += hit;
        }
        if (expected_area(id) >= config.large_area_m2) {
            ++ev.removed_large.truth;
            ev.removed_large.truth_matched += hit;
        }
    }
    for (const auto& [id, e] : found.elements) {
        if (e.verdict != "missing") continue;
        const bool true_removed =
            std::find(truth.removed.begin(), truth.removed.end(), id) != truth.removed.end();
        ++ev.removed.found;
        ev.removed.found_matched += true_removed;
        ++ev.removed_seen.found;
        ev.removed_seen.found_matched += true_removed;
        if (e.expected_area_m2 >= config.large_area_m2) {
            ++ev.removed_large.found;
            ev.removed_large.found_matched += true_removed;
        }
    }

    // Moved elements and as-built walls.
    for (const TruthChanges::Moved& m : truth.moved) {
        const auto it = found.elements.find(m.global_id);
        if (m.reason == "moved") {
            ChangeEvaluation::MovedScore s;
            s.global_id = m.global_id;
            s.true_translation_m = m.translation.norm();
            if (it != found.elements.end() && it->second.moved) {
                s.found = true;
                s.translation_error_m = (it->second.offset - m.translation).norm();
                s.yaw_error_deg =
                    std::abs(std::remainder(it->second.moved_yaw_deg - m.yaw_deg, 360.0));
            }
            ev.moved.push_back(s);
            continue;
        }
        if (found.datum.contains(m.global_id)) {
            ++ev.walls_datum;
            continue;
        }
        if (it == found.elements.end() || it->second.support_points < config.min_support_points) {
            ++ev.walls_unobserved;
            continue;
        }
        ChangeEvaluation::WallScore w;
        w.global_id = m.global_id;
        const double norm = m.translation.norm();
        const Eigen::Vector3d dir =
            norm > 0 ? Eigen::Vector3d(m.translation / norm) : Eigen::Vector3d::UnitX();
        w.true_offset_m = norm;
        w.measured_offset_m = it->second.offset.dot(dir);
        w.error_m = (it->second.offset - m.translation).norm();
        w.verdict = it->second.verdict;
        ev.walls.push_back(w);
    }

    // People.
    for (const TruthChanges::Person& p : truth.people) {
        ++ev.people;
        const double reach = p.radius_m + config.person_margin_m;
        for (size_t f = 0; f < found.objects.size(); ++f) {
            // A true added object, whoever walks by it.
            if (found_match[f] >= 0 || grouped_match[f] >= 0) continue;
            const Eigen::AlignedBox3d& box = found.objects[f].box;
            const Eigen::Vector2d c = box.center().head<2>();
            const bool on_line = DistanceToSegment(c, p.from, p.to) <= reach;
            const bool in_height =
                box.max().z() > p.floor_z && box.min().z() < p.floor_z + p.height_m;
            ev.people_as_objects += on_line && in_height;
        }
        bool transient = false;
        for (const Eigen::Vector3d& c : found.transients) {
            transient |= DistanceToSegment(c.head<2>(), p.from, p.to) <= reach;
        }
        ev.people_with_transients += transient;
    }
    return ev;
}

json ChangeEvaluation::SeenJson() const {
    json objects = json::array(), removed_elements = json::array();
    for (const AddedView& v : added_view) {
        objects.push_back({{"name", v.name},
                           {"large", v.large},
                           {"in_view", v.in_view},
                           {"found", v.found},
                           {"beam_hits", v.beam_hits},
                           {"map_points", v.map_points},
                           {"multi_view_points", v.multi_view_points}});
        if (!v.seen_box.isEmpty()) {
            objects.back()["seen_box_min"] = {v.seen_box.min().x(), v.seen_box.min().y(),
                                              v.seen_box.min().z()};
            objects.back()["seen_box_max"] = {v.seen_box.max().x(), v.seen_box.max().y(),
                                              v.seen_box.max().z()};
        }
    }
    for (const RemovedView& v : removed_view) {
        removed_elements.push_back({{"global_id", v.global_id},
                                    {"in_view", v.in_view},
                                    {"found", v.found},
                                    {"beam_hits", v.beam_hits},
                                    {"expected_area_m2", v.expected_area_m2}});
    }
    return {{"rule",
             {{"min_map_points", in_view_rule.min_points},
              {"min_multi_view_fraction", in_view_rule.min_multi_view_fraction},
              {"on_object_m", in_view_rule.on_object_m},
              {"off_model_m", in_view_rule.off_model_m},
              {"min_expected_area_m2", in_view_rule.min_area_m2}}},
            {"added", Scores(added_seen)},
            {"added_large", Scores(added_seen_large)},
            {"removed", Scores(removed_seen)},
            {"out_of_view",
             {{"added", added_out_of_view},
              {"added_large", added_large_out_of_view},
              {"removed", removed_out_of_view}}},
            {"no_beam",
             {{"added", added_no_beam},
              {"added_large", added_large_no_beam},
              {"removed", removed_no_beam}}},
            {"objects", objects},
            {"removed_elements", removed_elements}};
}

json ChangeEvaluation::ToJson() const {
    json moved_json = json::array(), walls_json = json::array();
    for (const MovedScore& m : moved) {
        moved_json.push_back({{"global_id", m.global_id},
                              {"found", m.found},
                              {"true_translation_m", m.true_translation_m},
                              {"translation_error_m", m.translation_error_m},
                              {"yaw_error_deg", m.yaw_error_deg}});
    }
    double max_error = 0, sum_error = 0;
    size_t within_1cm = 0;
    for (const WallScore& w : walls) {
        walls_json.push_back({{"global_id", w.global_id},
                              {"true_offset_m", w.true_offset_m},
                              {"measured_offset_m", w.measured_offset_m},
                              {"error_m", w.error_m},
                              {"verdict", w.verdict}});
        max_error = std::max(max_error, w.error_m);
        sum_error += w.error_m;
        within_1cm += w.error_m <= 0.01;
    }
    return {{"added", Scores(added)},
            {"added_large", Scores(added_large)},
            {"added_separable", Scores(added_separable)},
            {"added_separable_large", Scores(added_separable_large)},
            {"touching_groups", touching_groups},
            {"seen", SeenJson()},
            {"removed", Scores(removed)},
            {"removed_large", Scores(removed_large)},
            {"moved", moved_json},
            {"as_built",
             {{"walls", walls_json},
              {"observed", walls.size()},
              {"unobserved", walls_unobserved},
              {"surveyed", walls_datum},
              {"within_1cm", within_1cm},
              {"mean_error_m", walls.empty() ? 0.0 : sum_error / double(walls.size())},
              {"max_error_m", max_error}}},
            {"people",
             {{"people", people},
              {"reported_as_new_objects", people_as_objects},
              {"with_transient_clusters", people_with_transients}}}};
}

}  // namespace bimslam::change_detection
