#include "host_tools/changes/change_bcf.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "algorithms/common/status.hpp"
#include "algorithms/common/stopwatch.hpp"
#include "algorithms/common/utc_time.hpp"
#include "algorithms/simulation/scene.hpp"
#include "host_tools/changes/bim_change_model.hpp"

namespace bimslam::change_detection {
namespace {
using changes::kNoElement;

constexpr double kFovDeg = 60;
const Rgb kMissingColor{230, 30, 30}, kDeviatingColor{255, 140, 0}, kMovedFromColor{200, 40, 200},
    kMovedToColor{40, 160, 220};

std::string Hex(const Rgb& c) {
    char s[8];
    std::snprintf(s, sizeof s, "%02X%02X%02X", c[0], c[1], c[2]);
    return s;
}

std::string Fix(double v, int digits) {
    if (std::abs(v) < 0.5 * std::pow(10.0, -digits)) v = 0;  // no "-0.0"
    char s[32];
    std::snprintf(s, sizeof s, "%.*f", digits, v);
    return s;
}

std::string Cm(double m) { return Fix(100 * m, 1) + " cm"; }

std::string Xyz(const Eigen::Vector3d& v, int digits = 2) {
    return "(" + Fix(v.x(), digits) + ", " + Fix(v.y(), digits) + ", " + Fix(v.z(), digits) + ")";
}

// Where a change is and how large: a box in the mesh's frame.
struct Box {
    Eigen::Vector3d min = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
    Eigen::Vector3d max = Eigen::Vector3d::Constant(-std::numeric_limits<double>::max());
    void Add(const Eigen::Vector3d& p) { min = min.cwiseMin(p), max = max.cwiseMax(p); }
    Eigen::Vector3d centre() const { return 0.5 * (min + max); }
    Eigen::Vector3d size() const { return max - min; }
};

Box ElementBox(const bim::BimModel& model, size_t e) {
    Box b;
    const bim::BimElement& el = model.elements[e];
    for (uint32_t t = el.first_triangle; t < el.first_triangle + el.triangle_count; ++t) {
        for (const uint32_t v : model.mesh.triangles[t])
            b.Add(model.mesh.vertices[v].cast<double>());
    }
    return b;
}

// The camera: at the nearest keyframe whose line to the change's centre no other element
// crosses, at least far enough that the change fills about the view (1.5 .. 6 m), looking at it.
class CameraChooser {
public:
    CameraChooser(const bim::BimModel& model, const SessionChanges& found) {
        // Opaque physical elements: what hides a change (doors and glass do not).
        common::TriangleMesh mesh;
        std::vector<uint32_t> ids;
        mesh.vertices = model.mesh.vertices;
        for (size_t e = 0; e < model.elements.size(); ++e) {
            const bim::BimElement& el = model.elements[e];
            if (!Physical(el) || bim::PassThrough(el.ifc_class)) continue;
            for (uint32_t t = el.first_triangle; t < el.first_triangle + el.triangle_count; ++t) {
                mesh.triangles.push_back(model.mesh.triangles[t]);
                ids.push_back(uint32_t(e));
            }
        }
        simulation::SceneConfig config;
        config.high_quality_build = false;
        scene_.emplace(mesh, ids, config);
        // The poses the changes were measured on: refined, else as anchored.
        const auto& refined = found.result.refinement.T_world_lidar;
        for (size_t k = 0; k < found.input->keyframes.size(); ++k) {
            eyes_.push_back(k < refined.size()
                                ? refined[k].translation()
                                : found.input->keyframes[k].T_world_lidar.translation());
        }
    }

    // `element`: the change's own element (a ray that reaches it sees it), or -1.
    std::pair<SnapshotCamera, int> Choose(const Box& box, int element) const {
        const Eigen::Vector3d c = box.centre();
        const double radius = 0.5 * box.size().norm();
        const double wanted = std::clamp(0.9 * box.size().maxCoeff(), 1.5, 6.0);
        int best = -1, nearest = -1;
        double best_score = std::numeric_limits<double>::max(), nearest_d = best_score;
        for (size_t k = 0; k < eyes_.size(); ++k) {
            const double d = (c - eyes_[k]).norm();
            if (d < nearest_d) nearest_d = d, nearest = int(k);
            if (d < 1e-3 || !Sees(eyes_[k], c, radius, element)) continue;
            // Nearest at `wanted` or beyond; nearer ones only when none is that far.
            const double score = d >= wanted ? d : 1e6 + (wanted - d);
            if (score < best_score) best_score = score, best = int(k);
        }
        if (best < 0) best = nearest;
        SnapshotCamera cam;
        cam.fov_deg = kFovDeg;
        if (best < 0) {  // no keyframe: from above the change
            cam.eye = c + Eigen::Vector3d(-wanted, -wanted, wanted);
        } else {
            cam.eye = eyes_[size_t(best)];
        }
        cam.direction = (c - cam.eye).normalized();
        Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
        if (std::abs(cam.direction.dot(up)) > 0.99) up = Eigen::Vector3d::UnitY();
        cam.up = (up - up.dot(cam.direction) * cam.direction).normalized();
        return {cam, best};
    }

private:
    bool Sees(const Eigen::Vector3d& eye, const Eigen::Vector3d& c, double radius,
              int element) const {
        const Eigen::Vector3d d = c - eye;
        const auto hit = scene_->Intersect(eye.cast<float>(), d.cast<float>(), 0.f, 1.f);
        if (!hit) return true;
        if (element >= 0 && hit->id == uint32_t(element)) return true;
        return (1.0 - hit->t) * d.norm() < radius;  // within the change itself
    }

    std::optional<simulation::Scene> scene_;
    std::vector<Eigen::Vector3d> eyes_;
};

std::string Where(const bim::BimModel& model, int storey, int space) {
    std::string s;
    if (storey >= 0) s += "storey '" + model.storeys[size_t(storey)].name + "'";
    if (space >= 0) {
        const bim::BimElement& sp = model.elements[size_t(space)];
        s += std::string(s.empty() ? "" : ", ") + "IfcSpace '" + sp.name + "' (" + sp.global_id +
             ")";
    }
    return s.empty() ? "the model (no storey)" : s;
}

std::string Short(const bim::BimModel& model, int storey) {
    return storey >= 0 ? ", " + model.storeys[size_t(storey)].name : std::string();
}

}  // namespace

std::vector<ChangeTopic> ChangeTopics(const bim::BimModel& model, const SessionChanges& found,
                                      const changes::ChangeDetectorConfig& config,
                                      int64_t date_ns) {
    const changes::ChangeResult& r = found.result;
    const Eigen::Vector3d o = model.origin_m;
    const double tol = config.elements.deviation_tolerance_m;
    const CameraChooser chooser(model, found);
    const std::string seed = found.label + "/" + std::to_string(date_ns) + "/";
    std::vector<ChangeTopic> out;
    std::vector<int> storeys;  // per topic
    std::vector<Box> boxes;

    auto add = [&](const std::string& key, const char* type, const std::string& priority,
                   const Box& box, int element, const std::string& global_id, const Rgb& color) {
        ChangeTopic t;
        t.topic.guid = NameGuid(seed + key);
        t.topic.type = type;
        t.topic.status = "Open";
        t.topic.priority = priority;
        t.topic.creation_date = common::FormatUtcTime(date_ns);
        t.topic.author = "bimslam";
        t.topic.index = int(out.size()) + 1;
        t.topic.reference_file = "model_updated.ifc";
        t.target = box.centre();
        std::tie(t.camera, t.keyframe) = chooser.Choose(box, element);
        BcfViewpoint& vp = t.topic.viewpoint;
        vp.guid = NameGuid(seed + key + "/viewpoint");
        vp.eye = t.camera.eye + o;
        vp.direction = t.camera.direction;
        vp.up = t.camera.up;
        vp.fov_deg = t.camera.fov_deg;
        vp.selected = {global_id};
        vp.colors = {{Hex(color), {global_id}}};
        t.topic.labels = {type};
        out.push_back(std::move(t));
        boxes.push_back(box);
    };

    // New objects (a moved element's object is reported with the element).
    for (size_t k = 0; k < r.objects.size(); ++k) {
        const changes::NewObject& obj = r.objects[k];
        if (obj.moved_element != kNoElement) continue;
        Box box;
        box.Add(obj.box_min), box.Add(obj.box_max);
        const Eigen::Vector3d size = obj.box_max - obj.box_min;
        const double largest = size.maxCoeff();
        const char* priority = largest >= 1.0 ? "High" : largest >= 0.3 ? "Normal" : "Low";
        const Rgb color = ObjectColor(k);
        const std::string& gid = found.object_global_ids[k];
        add("object/" + std::to_string(k), kTopicNewObject, priority, box, -1, gid, color);
        ChangeTopic& t = out.back();
        const ObjectPlace& place = found.places[k];
        t.highlight.meshes = {{&obj.mesh, color}};
        t.topic.title = "New object " + std::to_string(k) + ": " + Fix(size.x(), 2) + " x " +
                        Fix(size.y(), 2) + " x " + Fix(size.z(), 2) + " m" +
                        Short(model, place.storey);
        t.topic.description = "An object that is not in the model, in " +
                              Where(model, place.storey, place.space) + ": " + Fix(size.x(), 2) +
                              " m x " + Fix(size.y(), 2) + " m x " + Fix(size.z(), 2) + " m (" +
                              Fix(obj.volume_m3, 3) + " m3, " + std::to_string(obj.points.size()) +
                              " map points), centred at " + Xyz(obj.centroid + o) +
                              " m in the model's coordinates. model_updated.ifc holds it as the "
                              "IfcBuildingElementProxy 'bimslam new object " +
                              std::to_string(k) + "' (" + gid + "). Session " + found.label + ".";
        storeys.push_back(place.storey);
    }

    // Missing, deviating and moved elements.
    for (int pass = 0; pass < 3; ++pass) {
        for (size_t e = 0; e < r.elements.size(); ++e) {
            const bim::BimElement& el = model.elements[e];
            const changes::ElementReport& rep = r.elements[e];
            if (!Physical(el)) continue;
            const bool missing = rep.verdict == changes::Verdict::kMissing;
            const bool deviating = rep.verdict == changes::Verdict::kDeviating && !rep.moved;
            const bool moved = rep.verdict == changes::Verdict::kDeviating && rep.moved;
            if (!(pass == 0 ? missing : pass == 1 ? deviating : moved)) continue;
            const std::string what = el.ifc_class + " '" + el.name + "' (" + el.global_id + ")";
            const int storey = ElementStorey(model, e);
            Box box = ElementBox(model, e);
            const changes::NewObject* to =
                moved && rep.moved_object >= 0 ? &r.objects[size_t(rep.moved_object)] : nullptr;
            if (to) box.Add(to->box_min), box.Add(to->box_max);
            const double n = rep.offset.norm();
            if (missing) {
                const bool structure = el.role == bim::ElementRole::kStructure;
                add("missing/" + el.global_id, kTopicMissing, structure ? "High" : "Normal", box,
                    int(e), el.global_id, kMissingColor);
                ChangeTopic& t = out.back();
                t.topic.title =
                    "Missing: " + el.ifc_class + " '" + el.name + "'" + Short(model, storey);
                t.topic.description =
                    "The model's " + what +
                    " was not found where the model has it: the walk's "
                    "beams went through " +
                    Fix(rep.evidence.expected_area_m2 - rep.evidence.seen_area_m2, 2) +
                    " m2 of the " + Fix(rep.evidence.expected_area_m2, 2) +
                    " m2 of it they reached (" + std::to_string(rep.evidence.rays_through) +
                    " beams through it, " + std::to_string(rep.evidence.rays_agree) +
                    " on it). Session " + found.label + ".";
                t.highlight.element = int(e);
                t.highlight.element_color = kMissingColor;
            } else if (deviating) {
                const char* priority = n < 2 * tol ? "Low" : n < 5 * tol ? "Normal" : "High";
                add("deviating/" + el.global_id, kTopicDeviating, priority, box, int(e),
                    el.global_id, kDeviatingColor);
                ChangeTopic& t = out.back();
                t.topic.title = "Deviation " + Cm(n) + ": " + el.ifc_class + " '" + el.name + "'" +
                                Short(model, storey);
                t.topic.description =
                    "The model's " + what + " stands " + Cm(n) +
                    " from where the model has it (offset x, y, z " + Xyz(100 * rep.offset, 1) +
                    " cm; the tolerance is " + Cm(tol) + "), measured on " +
                    std::to_string(rep.support_points) + " map points (mean signed distance " +
                    Cm(rep.mean_signed_m) + ", largest " + Cm(rep.max_signed_m) + "). Session " +
                    found.label + ".";
                t.highlight.element = int(e);
                t.highlight.element_color = kDeviatingColor;
            } else {
                const bool far = n >= 0.5 || std::abs(rep.moved_yaw_deg) >= 30;
                add("moved/" + el.global_id, kTopicMoved, far ? "High" : "Normal", box, int(e),
                    el.global_id, kMovedFromColor);
                ChangeTopic& t = out.back();
                t.topic.title = "Moved " + Fix(n, 2) + " m: " + el.ifc_class + " '" + el.name +
                                "'" + Short(model, storey);
                t.topic.description =
                    "The model's " + what + " stands elsewhere: moved by " + Xyz(rep.offset) +
                    " m (" + Fix(n, 2) + " m) and turned " + Fix(rep.moved_yaw_deg, 1) +
                    " degrees about the vertical. The picture shows where the model has it (" +
                    Hex(kMovedFromColor) + ") and where it was seen (" + Hex(kMovedToColor) +
                    "). Session " + found.label + ".";
                t.highlight.element = int(e);
                t.highlight.element_color = kMovedFromColor;
                if (to) t.highlight.meshes = {{&to->mesh, kMovedToColor}};
            }
            storeys.push_back(storey);
        }
    }

    // The space of each element change: the one holding its base's centre, else the one the
    // camera looks from, just before its line of sight enters the change's box (a wall bounds its
    // spaces and is in none).
    std::vector<Eigen::Vector3f> at, beside;
    for (size_t i = 0; i < out.size(); ++i) {
        const Box& b = boxes[i];
        at.emplace_back(
            Eigen::Vector3d(b.centre().x(), b.centre().y(), b.min.z() + 0.1).cast<float>());
        const Eigen::Vector3d eye = out[i].camera.eye, d = b.centre() - eye;
        double enter = 0;  // along d, where the ray enters the box (slab method)
        for (int k = 0; k < 3; ++k) {
            if (std::abs(d[k]) < 1e-12) continue;
            const double t0 = (b.min[k] - eye[k]) / d[k], t1 = (b.max[k] - eye[k]) / d[k];
            enter = std::max(enter, std::min(t0, t1));
        }
        const double back = d.norm() > 0 ? 0.2 / d.norm() : 0;
        beside.push_back((eye + std::clamp(enter - back, 0.0, 1.0) * d).cast<float>());
    }
    const std::vector<int> s1 = SpacesAt(model, at), s2 = SpacesAt(model, beside);
    for (size_t i = 0; i < out.size(); ++i) {
        if (storeys[i] >= 0 && !model.storeys[size_t(storeys[i])].name.empty())
            out[i].topic.labels.push_back(model.storeys[size_t(storeys[i])].name);
        if (out[i].topic.type == kTopicNewObject) continue;  // its description has it already
        const int space = s1[i] >= 0 ? s1[i] : s2[i];
        out[i].topic.description += " Where: " + Where(model, storeys[i], space) + ".";
    }
    return out;
}

ChangeBcf ChangesBcf(const bim::BimModel& model, const SessionChanges& found,
                     const changes::ChangeDetectorConfig& config, const ChangeBcfOptions& options,
                     SnapshotRenderer& renderer) {
    ChangeBcf out;
    const auto t0 = common::SteadyClock::now();
    std::vector<ChangeTopic> topics = ChangeTopics(model, found, config, options.date_ns);
    out.topics_s = common::SecondsSince(t0);
    std::vector<BcfTopic> bcf;
    for (ChangeTopic& t : topics) {
        const auto r0 = common::SteadyClock::now();
        const io::Image image = renderer.Render(t.camera, t.highlight);
        out.render_s += common::SecondsSince(r0);
        const auto p0 = common::SteadyClock::now();
        t.topic.viewpoint.snapshot_png = EncodePngLibpng(image);
        t.topic.viewpoint.aspect = double(renderer.width()) / renderer.height();
        out.png_s += common::SecondsSince(p0);
        bcf.push_back(std::move(t.topic));
    }
    const auto z0 = common::SteadyClock::now();
    out.zip = BcfZip(ChangesBcfProject(model, options.model_sha256), bcf, options.version,
                     options.date_ns);
    out.zip_s = common::SecondsSince(z0);
    out.topics = bcf.size();
    return out;
}

BcfProject ChangesBcfProject(const bim::BimModel& model, const std::string& model_sha256) {
    BcfProject p;
    p.id = NameGuid("bimslam project " + model_sha256);
    p.name = std::filesystem::path(model.file).filename().string();
    p.topic_types = {kTopicNewObject, kTopicMissing, kTopicDeviating, kTopicMoved};
    p.topic_statuses = {"Open"};
    p.priorities = {"Low", "Normal", "High"};
    p.labels = p.topic_types;
    for (const bim::BimStorey& s : model.storeys) {
        if (std::find(p.labels.begin(), p.labels.end(), s.name) == p.labels.end())
            p.labels.push_back(s.name);
    }
    p.users = {"bimslam"};
    return p;
}

int64_t SessionDate(const SessionInput& input) {
    constexpr int64_t kYear2000Ns = 946684800LL * 1000000000LL;
    const auto& kf = input.session.keyframes;
    if (!kf.empty() && kf.front().stamp_ns >= kYear2000Ns) return kf.front().stamp_ns;
    try {
        return common::ParseUtcTime(input.session.manifest.created);
    } catch (const common::Error&) {
        return 0;
    }
}

}  // namespace bimslam::change_detection
