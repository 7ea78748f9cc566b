// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/changes/change_report.hpp"

#include <cmath>
#include <map>
#include <sstream>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/ply.hpp"
#include "algorithms/io/trajectory.hpp"
#include "host_tools/changes/map_las.hpp"

namespace bimslam::change_detection {
namespace {
using changes::kNoElement;
using nlohmann::json;

json Vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// A CSV field: quoted when it holds a comma, a quote or a line break (RFC 4180).
std::string Csv(const std::string& s) {
    if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
    std::string out = "\"";
    for (const char c : s) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + "\"";
}

std::string Num(double v) { return io::FormatDouble(v); }

// A change's storey: `from` says how it was placed: "ifc" (the element's IfcBuildingStorey) or
// "height" (the storey under its lowest point: new objects, elements of no storey).
json StoreyJson(const bim::BimModel& model, int storey, const char* from) {
    if (storey < 0 || size_t(storey) >= model.storeys.size()) return nullptr;
    return {{"index", storey},
            {"name", model.storeys[size_t(storey)].name},
            {"global_id", model.storeys[size_t(storey)].global_id},
            {"from", from}};
}

json ElementJson(const bim::BimModel& model, size_t e) {
    const bim::BimElement& el = model.elements[e];
    bool from_height = false;
    const int storey = ElementStorey(model, e, &from_height);
    return {{"index", e},
            {"global_id", el.global_id},
            {"class", el.ifc_class},
            {"name", el.name},
            {"storey", StoreyJson(model, storey, from_height ? "height" : "ifc")}};
}

}  // namespace

// What the joint refinement of the poses did (algorithms/changes/pose_refinement.hpp).
json RefinementJson(const changes::PoseRefinement& p, bool enabled) {
    if (!enabled) return {{"enabled", false}};
    return {{"enabled", true},
            {"keyframes", p.T_world_lidar.size()},
            {"edges", p.edges},
            {"unexplained", p.unexplained},
            {"held", p.held},
            {"correspondences", p.correspondences},
            {"datum_seen", p.datum_seen},
            {"poses_moved_1cm", p.moved_1cm},
            {"mean_correction_m", p.mean_correction_m},
            {"max_correction_m", p.max_correction_m},
            {"max_correction_deg", p.max_correction_deg},
            {"iterations", p.iterations}};
}

std::array<uint8_t, 3> ObjectColor(size_t i) {
    // Hue by the golden angle, full saturation, value 0.9: neighbouring indices differ most.
    const double h = std::fmod(double(i) * 137.50776405, 360.0) / 60.0;
    const double v = 0.9, c = v, x = c * (1 - std::abs(std::fmod(h, 2.0) - 1));
    double r = 0, g = 0, b = 0;
    switch (int(h)) {
        case 0:
            r = c, g = x;
            break;
        case 1:
            r = x, g = c;
            break;
        case 2:
            g = c, b = x;
            break;
        case 3:
            g = x, b = c;
            break;
        case 4:
            r = x, b = c;
            break;
        default:
            r = c, b = x;
            break;
    }
    return {uint8_t(std::lround(255 * r)), uint8_t(std::lround(255 * g)),
            uint8_t(std::lround(255 * b))};
}

namespace {

// changes.json's "new_objects": each object (not a moved element's, reported with its element),
// with its place and its mesh's range in new_objects.ply.
json NewObjectsJson(const bim::BimModel& model, const SessionChanges& found) {
    const changes::ChangeResult& r = found.result;
    const Eigen::Vector3d o = model.origin_m;
    json objects = json::array();
    size_t vertex = 0, triangle = 0;
    for (size_t k = 0; k < r.objects.size(); ++k) {
        const changes::NewObject& obj = r.objects[k];
        if (obj.moved_element != kNoElement) continue;  // reported with its element
        const ObjectPlace& place = found.places[k];
        const auto color = ObjectColor(k);
        json space = nullptr;
        if (place.space >= 0) {
            const bim::BimElement& s = model.elements[size_t(place.space)];
            space = {{"global_id", s.global_id}, {"name", s.name}, {"long_name", s.long_name}};
        }
        const Eigen::Vector2d plan = obj.plan.center + o.head<2>();
        objects.push_back({{"id", k},
                           {"ifc_global_id", found.object_global_ids[k]},
                           {"points", obj.points.size()},
                           {"box_min", Vec(obj.box_min + o)},
                           {"box_max", Vec(obj.box_max + o)},
                           {"size_m", Vec(obj.box_max - obj.box_min)},
                           {"centroid", Vec(obj.centroid + o)},
                           {"volume_m3", obj.volume_m3},
                           {"plan_size_m", {obj.plan.long_m, obj.plan.short_m}},
                           {"plan_yaw_deg", obj.plan.yaw_deg},
                           {"plan_center_m", {plan.x(), plan.y()}},
                           {"voxels", obj.solid.voxels.size()},
                           {"on_floor", obj.on_floor},
                           {"outside_footprint", obj.outside_footprint},
                           {"storey", StoreyJson(model, place.storey, "height")},
                           {"space", space},
                           {"color", {color[0], color[1], color[2]}},
                           {"mesh",
                            {{"file", "new_objects.ply"},
                             {"first_vertex", vertex},
                             {"vertices", obj.mesh.vertices.size()},
                             {"first_triangle", triangle},
                             {"triangles", obj.mesh.triangles.size()}}}});
        vertex += obj.mesh.vertices.size();
        triangle += obj.mesh.triangles.size();
    }

    return objects;
}

// changes.json's "missing" and "deviating" elements, and how many were confirmed and not observed.
struct ElementLists {
    json missing, deviating;
    size_t confirmed = 0, not_observed = 0;
};

ElementLists ElementsJson(const bim::BimModel& model, const changes::ChangeResult& r) {
    ElementLists out{json::array(), json::array()};
    for (size_t e = 0; e < r.elements.size(); ++e) {
        if (!Listed(model.elements[e])) continue;
        const changes::ElementReport& rep = r.elements[e];
        json j = ElementJson(model, e);
        j["expected_area_m2"] = rep.evidence.expected_area_m2;
        j["seen_area_m2"] = rep.evidence.seen_area_m2;
        j["rays_agree"] = rep.evidence.rays_agree;
        j["rays_through"] = rep.evidence.rays_through;
        switch (rep.verdict) {
            case changes::Verdict::kMissing:
                out.missing.push_back(j);
                break;
            case changes::Verdict::kDeviating: {
                j["offset_m"] = Vec(rep.offset);
                j["offset_norm_m"] = rep.offset.norm();
                j["constrained_axes"] = rep.constrained_axes;
                j["support_points"] = rep.support_points;
                j["mean_signed_m"] = rep.mean_signed_m;
                j["max_signed_m"] = rep.max_signed_m;
                j["rms_m"] = rep.rms_m;
                j["moved"] = nullptr;
                if (rep.moved) {
                    j["moved"] = {
                        {"translation_m", Vec(rep.offset)},
                        {"yaw_deg", rep.moved_yaw_deg},
                        {"inlier_fraction", rep.moved_inlier_fraction},
                        {"object_points", r.objects[size_t(rep.moved_object)].points.size()}};
                }
                out.deviating.push_back(j);
                break;
            }
            case changes::Verdict::kConfirmed:
                ++out.confirmed;
                break;
            case changes::Verdict::kNotObserved:
                ++out.not_observed;
                break;
        }
    }

    return out;
}

// changes.json's "transients": the clusters other keyframes looked through, with when.
json TransientsJson(const bim::BimModel& model, const SessionChanges& found) {
    const changes::ChangeResult& r = found.result;
    const Eigen::Vector3d o = model.origin_m;
    const io::Session& session = found.input->session;
    json transients = json::array();
    for (size_t k = 0; k < r.transients.size(); ++k) {
        const changes::TransientCluster& t = r.transients[k];
        transients.push_back({{"id", k},
                              {"points", t.points.size()},
                              {"box_min", Vec(t.box_min + o)},
                              {"box_max", Vec(t.box_max + o)},
                              {"centroid", Vec(t.centroid + o)},
                              {"first_keyframe", t.first_keyframe},
                              {"last_keyframe", t.last_keyframe},
                              {"first_stamp_ns", session.keyframes[t.first_keyframe].stamp_ns},
                              {"last_stamp_ns", session.keyframes[t.last_keyframe].stamp_ns}});
    }

    return transients;
}

// changes.json's "parameters": the configuration the changes were found with.
json ParametersJson(const bim::BimModel& model, const changes::ChangeDetectorConfig& config) {
    const changes::ChangeDetectorConfig& c = config;
    json datum = json::array();
    for (const changes::SurveyedElement& d : c.refinement.datum) {
        datum.push_back(
            {{"global_id", model.elements.at(d.element).global_id}, {"offset_m", Vec(d.offset)}});
    }
    json parameters = {{"voxel_m", c.map.voxel_m},
                       {"min_range_m", c.map.min_range_m},
                       {"max_range_m", c.map.max_range_m},
                       {"new_object_threshold_m", c.new_object_threshold_m},
                       {"band_threshold_m", c.band_threshold_m},
                       {"dbscan", {{"eps_m", c.dbscan.eps_m}, {"min_points", c.dbscan.min_points}}},
                       {"min_object_points", c.min_object_points},
                       {"min_multi_view_fraction", c.min_multi_view_fraction},
                       {"max_unseen_support_drop_m", c.max_unseen_support_drop_m},
                       {"crop_margin_m", c.crop_margin_m},
                       {"crop_to_footprint", c.crop_to_footprint},
                       {"extension_margin_m", c.extension_margin_m},
                       {"extension_clearance_m", c.extension_clearance_m},
                       {"walls",
                        {{"split_corners", c.walls.split_corners},
                         {"join_hidden_gaps", c.walls.join_hidden_gaps},
                         {"plane_tolerance_m", c.walls.plane_tolerance_m},
                         {"min_on_planes", c.walls.min_on_planes},
                         {"min_wall_length_m", c.walls.min_wall_length_m},
                         {"min_wall_height_m", c.walls.min_wall_height_m},
                         {"max_gap_m", c.walls.max_gap_m},
                         {"max_looked_through", c.walls.max_looked_through}}},
                       {"transients",
                        {{"enabled", c.detect_transients},
                         {"patch_radius_m", c.free_space.patch_radius_m},
                         {"min_crossing_cos", c.free_space.min_crossing_cos},
                         {"range_margin_m", c.free_space.range_margin_m},
                         {"min_free_keyframes", c.free_space.min_free_keyframes},
                         {"free_over_seen", c.free_space.free_over_seen},
                         {"unjudged_radius_m", c.free_space.unjudged_radius_m},
                         {"max_range_m", c.free_space.max_range_m}}},
                       {"elements",
                        {{"agree_tolerance_m", c.evidence.agree_tolerance_m},
                         {"cell_m", c.evidence.cell_m},
                         {"support_distance_m", c.elements.support_distance_m},
                         {"deviation_tolerance_m", c.elements.deviation_tolerance_m},
                         {"tolerance_m", c.elements.tolerance_m},
                         {"min_support_points", c.elements.min_support_points},
                         {"min_judged_area_m2", c.elements.min_judged_area_m2},
                         {"missing_seen_fraction", c.elements.missing_seen_fraction}}},
                       {"moved",
                        {{"enabled", c.moved.enabled},
                         {"max_seen_fraction", c.moved.max_seen_fraction},
                         {"pair_radius_m", c.moved.pair_radius_m},
                         {"inlier_m", c.moved.inlier_m},
                         {"min_inlier_fraction", c.moved.min_inlier_fraction},
                         {"min_object_fraction", c.moved.min_object_fraction},
                         {"min_extent_fraction", c.moved.min_extent_fraction},
                         {"sample_spacing_m", c.moved.sample_spacing_m},
                         {"sample_inset_m", c.moved.sample_inset_m},
                         {"max_looked_through", c.moved.max_looked_through},
                         {"min_judged_samples", c.moved.min_judged_samples}}},
                       {"refinement",
                        {{"enabled", c.refinement.enabled},
                         {"element_sigma_m", c.refinement.element_sigma_m},
                         {"point_sigma_m", c.refinement.point_sigma_m},
                         {"points_per_keyframe", c.refinement.points_per_keyframe},
                         {"gates_m", c.refinement.gates_m},
                         {"datum", datum},
                         {"datum_sigma_m", c.refinement.datum_sigma_m}}}};

    return parameters;
}

}  // namespace

json ChangesJson(const bim::BimModel& model, const ModelInfo& info, const SessionChanges& found,
                 const changes::ChangeDetectorConfig& config) {
    const changes::ChangeResult& r = found.result;
    const io::Session& session = found.input->session;
    const ElementLists elements = ElementsJson(model, r);
    std::map<std::string, size_t> classes;
    for (const changes::PointClass c : r.point_class) ++classes[std::string(changes::ToString(c))];

    return {{"format", "bimslam-changes"},
            {"version", 1},
            {"frame", "bim"},
            {"model",
             {{"file", info.file.string()},
              {"sha256", info.sha256},
              {"schema", model.schema},
              {"elements", model.elements.size()}}},
            {"session",
             {{"label", found.label},
              {"dir", found.input->dir.string()},
              {"source", session.manifest.source},
              {"keyframes", session.keyframes.size()},
              {"points", found.input->points}}},
            {"parameters", ParametersJson(model, config)},
            {"map",
             {{"file", "map_bim.ply"},
              {"points", r.map.size()},
              {"input_points", r.map.input_points},
              {"cropped_points", r.map.cropped_points},
              {"classes", classes}}},
            {"new_objects", NewObjectsJson(model, found)},
            {"missing", elements.missing},
            {"deviating", elements.deviating},
            {"confirmed", elements.confirmed},
            {"not_observed", elements.not_observed},
            {"transients", TransientsJson(model, found)},
            {"counts",
             {{"candidates", r.counts.candidates},
              {"outside_footprint", r.counts.outside_footprint},
              {"extension_points", r.counts.extension_points},
              {"transient_points", r.counts.transient_points},
              {"unjudged_points", r.counts.unjudged_points},
              {"transient_by_neighbours", r.counts.transient_by_neighbours},
              {"seed_points", r.counts.seed_points},
              {"clusters", r.counts.clusters},
              {"single_view_clusters", r.counts.single_view_clusters},
              {"refinement", RefinementJson(r.refinement, config.refinement.enabled)}}},
            {"seconds",
             {{"refinement", r.seconds.refinement_s},
              {"map", r.seconds.map_s},
              {"distances", r.seconds.distance_s},
              {"transients", r.seconds.transient_s},
              {"clusters", r.seconds.cluster_s},
              {"evidence", r.seconds.evidence_s},
              {"elements", r.seconds.elements_s}}}};
}

void WriteChangeFiles(const std::filesystem::path& dir, const bim::BimModel& model,
                      const ModelInfo& info, const SessionChanges& found,
                      const changes::ChangeDetectorConfig& config) {
    const changes::ChangeResult& r = found.result;
    const Eigen::Vector3f o = model.origin_m.cast<float>();
    io::WriteFileAtomic(dir / "changes.json",
                        ChangesJson(model, info, found, config).dump(2) + "\n");

    // The new objects' meshes, one after the other (the order of changes.json).
    io::PlyData objects;
    io::PlyProperty red{"red", io::PlyType::kUint8, {}}, green{"green", io::PlyType::kUint8, {}},
        blue{"blue", io::PlyType::kUint8, {}}, id{"object", io::PlyType::kInt32, {}};
    for (size_t k = 0; k < r.objects.size(); ++k) {
        const changes::NewObject& obj = r.objects[k];
        if (obj.moved_element != kNoElement) continue;
        const auto base = uint32_t(objects.vertices.size());
        const auto color = ObjectColor(k);
        for (const auto& v : obj.mesh.vertices) {
            objects.vertices.push_back(v + o);
            red.values.push_back(color[0]);
            green.values.push_back(color[1]);
            blue.values.push_back(color[2]);
            id.values.push_back(double(k));
        }
        for (const auto& t : obj.mesh.triangles) {
            objects.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
        }
    }
    objects.vertex_properties = {red, green, blue, id};
    io::WritePly(dir / "new_objects.ply", objects);

    // The map with its scalar fields, named scalar_* as CloudCompare writes (and, headless, only
    // reads) them, and of types Open3D's reader takes (it skips ushort).
    io::PlyData map;
    map.vertices.reserve(r.map.size());
    io::PlyProperty distance{"scalar_distance", io::PlyType::kFloat32, {}},
        element{"scalar_element", io::PlyType::kInt32, {}},
        keyframes{"scalar_keyframes", io::PlyType::kInt32, {}},
        cls{"scalar_class", io::PlyType::kUint8, {}},
        object{"scalar_object", io::PlyType::kInt32, {}};
    for (auto* p : {&distance, &element, &keyframes, &cls, &object})
        p->values.reserve(r.map.size());
    for (size_t i = 0; i < r.map.size(); ++i) {
        map.vertices.push_back(r.map.xyz[i] + o);
        const float d = r.signed_distance_m[i];
        distance.values.push_back(std::isfinite(d) ? d : 1e9);  // PLY floats must be finite
        element.values.push_back(r.element[i] == kNoElement ? -1.0 : double(r.element[i]));
        keyframes.values.push_back(r.map.keyframes[i]);
        cls.values.push_back(double(r.point_class[i]));
        object.values.push_back(r.object[i]);
    }
    map.vertex_properties = {distance, element, keyframes, cls, object};
    io::WritePly(dir / "map_bim.ply", map);
    io::WriteLas(dir / "map_bim.las", MapLas(r, model.origin_m, found.input->session, found.visit));

    std::ostringstream csv;
    csv << "index,global_id,class,name,storey,verdict,opaque,surface_area_m2,expected_area_m2,"
           "seen_area_m2,rays_agree,rays_through,rays_occluded,support_points,mean_signed_m,"
           "max_signed_m,rms_m,offset_x_m,offset_y_m,offset_z_m,offset_m,constrained_axes,"
           "residual_rms_m,moved,moved_yaw_deg,tolerance_verdict\n";
    for (size_t e = 0; e < r.elements.size(); ++e) {
        const bim::BimElement& el = model.elements[e];
        if (!Listed(el)) continue;
        const changes::ElementReport& rep = r.elements[e];
        const int s = ElementStorey(model, e);
        const std::string storey = s >= 0 ? model.storeys[size_t(s)].name : std::string();
        csv << e << ',' << Csv(el.global_id) << ',' << Csv(el.ifc_class) << ',' << Csv(el.name)
            << ',' << Csv(storey) << ',' << changes::ToString(rep.verdict) << ','
            << int(!bim::PassThrough(el.ifc_class)) << ',' << Num(rep.evidence.surface_area_m2)
            << ',' << Num(rep.evidence.expected_area_m2) << ',' << Num(rep.evidence.seen_area_m2)
            << ',' << rep.evidence.rays_agree << ',' << rep.evidence.rays_through << ','
            << rep.evidence.rays_occluded << ',' << rep.support_points << ','
            << Num(rep.mean_signed_m) << ',' << Num(rep.max_signed_m) << ',' << Num(rep.rms_m)
            << ',' << Num(rep.offset.x()) << ',' << Num(rep.offset.y()) << ','
            << Num(rep.offset.z()) << ',' << Num(rep.offset.norm()) << ',' << rep.constrained_axes
            << ',' << Num(rep.residual_rms_m) << ',' << int(rep.moved) << ','
            << Num(rep.moved_yaw_deg) << ','
            << changes::ToString(changes::JudgeTolerance(rep, config.elements)) << '\n';
    }
    io::WriteFileAtomic(dir / "elements.csv", csv.str());

    // The poses everything above was measured on, when the refinement moved them: T_bim_lidar in
    // the model's file coordinates, stamped as the session's keyframes (comparable with
    // the session's trajectory_bim.tum keyframe by keyframe, or a ground truth).
    if (!r.refinement.T_world_lidar.empty()) {
        std::vector<io::StampedPose> poses;
        for (size_t k = 0; k < r.refinement.T_world_lidar.size(); ++k) {
            Eigen::Isometry3d T = r.refinement.T_world_lidar[k];
            T.translation() += model.origin_m;
            poses.push_back(
                io::StampedPose::FromIsometry(found.input->session.keyframes[k].stamp_ns, T));
        }
        io::WriteTum(dir / "keyframes_refined.tum", poses);
    }
}

}  // namespace bimslam::change_detection
