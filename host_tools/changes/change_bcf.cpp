// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
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

std::string WhereIn(const bim::BimModel& model, int storey, int space) {
    std::string s;
    if (storey >= 0) s += "storey '" + model.storeys[size_t(storey)].name + "'";
    if (space >= 0) {
        // The space as people call it (its LongName), with its Name (often its number) beside.
        const bim::BimElement& sp = model.elements[size_t(space)];
        const std::string number = sp.long_name.empty() ? "" : sp.name + ", ";
        s += std::string(s.empty() ? "" : ", ") + "IfcSpace '" +
             (sp.long_name.empty() ? sp.name : sp.long_name) + "' (" + number + sp.global_id + ")";
    }
    return s.empty() ? "the model (no storey)" : s;
}

// The topics of one session, built change by change (ChangeTopics' order).
class TopicBuilder {
public:
    TopicBuilder(const bim::BimModel& model, const SessionChanges& found,
                 const changes::ChangeDetectorConfig& config, int64_t date_ns)
        : model_(model),
          found_(found),
          r_(found.result),
          chooser_(model, found),
          tol_(config.elements.deviation_tolerance_m),
          date_ns_(date_ns),
          seed_(found.label + "/" + std::to_string(date_ns) + "/") {}

    void NewObject(size_t k) {
        const changes::NewObject& obj = r_.objects[k];
        Box box;
        box.Add(obj.box_min), box.Add(obj.box_max);
        const Eigen::Vector3d size = obj.box_max - obj.box_min;
        const double largest = size.maxCoeff();
        const Rgb color = ObjectColor(k);
        const std::string& gid = found_.object_global_ids[k];
        const ObjectPlace& place = found_.places[k];
        ChangeTopic& t = Add("object/" + std::to_string(k), kTopicNewObject,
                             largest >= 1.0   ? "High"
                             : largest >= 0.3 ? "Normal"
                                              : "Low",
                             box, -1, gid, color, place.storey);
        t.highlight.meshes = {{&obj.mesh, color}};
        const std::string dims =
            Fix(size.x(), 2) + " m x " + Fix(size.y(), 2) + " m x " + Fix(size.z(), 2) + " m";
        t.topic.title = "New object " + std::to_string(k) + ": " + Fix(size.x(), 2) + " x " +
                        Fix(size.y(), 2) + " x " + Fix(size.z(), 2) + " m" + Short(place.storey);
        t.topic.description = "An object that is not in the model, in " +
                              Where(place.storey, place.space) + ": " + dims + " (" +
                              Fix(obj.volume_m3, 3) + " m3, " + std::to_string(obj.points.size()) +
                              " map points), centred at " + Xyz(obj.centroid + model_.origin_m) +
                              " m in the model's coordinates. model_updated.ifc holds it as the "
                              "IfcBuildingElementProxy 'bimslam new object " +
                              std::to_string(k) + "' (" + gid + "). Session " + found_.label + ".";
        has_space_.back() = true;  // its description has it already
    }

    void Missing(size_t e) {
        const bim::BimElement& el = model_.elements[e];
        const changes::ElementEvidence& ev = r_.elements[e].evidence;
        ChangeTopic& t = AddElement(e, "missing/", kTopicMissing,
                                    el.role == bim::ElementRole::kStructure ? "High" : "Normal",
                                    kMissingColor, nullptr);
        t.topic.title = "Missing: " + el.ifc_class + " '" + el.name + "'" + Short(storeys_.back());
        t.topic.description = "The model's " + What(el) +
                              " was not found where the model has it: the walk's beams "
                              "went through " +
                              Fix(ev.expected_area_m2 - ev.seen_area_m2, 2) + " m2 of the " +
                              Fix(ev.expected_area_m2, 2) + " m2 of it they reached (" +
                              std::to_string(ev.rays_through) + " beams through it, " +
                              std::to_string(ev.rays_agree) + " on it). Session " + found_.label +
                              ".";
    }

    void Deviating(size_t e) {
        const bim::BimElement& el = model_.elements[e];
        const changes::ElementReport& rep = r_.elements[e];
        const double n = rep.offset.norm();
        ChangeTopic& t = AddElement(e, "deviating/", kTopicDeviating,
                                    n < 2 * tol_   ? "Low"
                                    : n < 5 * tol_ ? "Normal"
                                                   : "High",
                                    kDeviatingColor, nullptr);
        t.topic.title = "Deviation " + Cm(n) + ": " + el.ifc_class + " '" + el.name + "'" +
                        Short(storeys_.back());
        t.topic.description = "The model's " + What(el) + " stands " + Cm(n) +
                              " from where the model has it (offset x, y, z " +
                              Xyz(100 * rep.offset, 1) + " cm; the tolerance is " + Cm(tol_) +
                              "), measured on " + std::to_string(rep.support_points) +
                              " map points (mean signed distance " + Cm(rep.mean_signed_m) +
                              ", largest " + Cm(rep.max_signed_m) + "). Session " + found_.label +
                              ".";
    }

    void Moved(size_t e) {
        const bim::BimElement& el = model_.elements[e];
        const changes::ElementReport& rep = r_.elements[e];
        const double n = rep.offset.norm();
        const changes::NewObject* to =
            rep.moved_object >= 0 ? &r_.objects[size_t(rep.moved_object)] : nullptr;
        const bool far = n >= 0.5 || std::abs(rep.moved_yaw_deg) >= 30;
        ChangeTopic& t =
            AddElement(e, "moved/", kTopicMoved, far ? "High" : "Normal", kMovedFromColor, to);
        if (to) t.highlight.meshes = {{&to->mesh, kMovedToColor}};
        t.topic.title = "Moved " + Fix(n, 2) + " m: " + el.ifc_class + " '" + el.name + "'" +
                        Short(storeys_.back());
        t.topic.description =
            "The model's " + What(el) + " stands elsewhere: moved by " + Xyz(rep.offset) + " m (" +
            Fix(n, 2) + " m) and turned " + Fix(rep.moved_yaw_deg, 1) +
            " degrees about the vertical. The picture shows where the model has it (" +
            Hex(kMovedFromColor) + ") and where it was seen (" + Hex(kMovedToColor) +
            "). Session " + found_.label + ".";
    }

    // Every topic's storey label, and an element change's space in its description: the space
    // holding the centre of its base, else the one the camera looks from, just before its line
    // of sight enters the change's box (a wall bounds its spaces and is in none).
    std::vector<ChangeTopic> Finish() {
        std::vector<Eigen::Vector3f> at, beside;
        for (size_t i = 0; i < out_.size(); ++i) {
            const Box& b = boxes_[i];
            at.emplace_back(
                Eigen::Vector3d(b.centre().x(), b.centre().y(), b.min.z() + 0.1).cast<float>());
            const Eigen::Vector3d eye = out_[i].camera.eye, d = b.centre() - eye;
            double enter = 0;  // along d, where the ray enters the box (slab method)
            for (int k = 0; k < 3; ++k) {
                if (std::abs(d[k]) < 1e-12) continue;
                const double t0 = (b.min[k] - eye[k]) / d[k], t1 = (b.max[k] - eye[k]) / d[k];
                enter = std::max(enter, std::min(t0, t1));
            }
            const double back = d.norm() > 0 ? 0.2 / d.norm() : 0;
            beside.push_back((eye + std::clamp(enter - back, 0.0, 1.0) * d).cast<float>());
        }
        const std::vector<int> s1 = SpacesAt(model_, at), s2 = SpacesAt(model_, beside);
        for (size_t i = 0; i < out_.size(); ++i) {
            const int storey = storeys_[i];
            if (storey >= 0 && !model_.storeys[size_t(storey)].name.empty())
                out_[i].topic.labels.push_back(model_.storeys[size_t(storey)].name);
            if (has_space_[i]) continue;
            out_[i].topic.description +=
                " Where: " + Where(storey, s1[i] >= 0 ? s1[i] : s2[i]) + ".";
        }
        return std::move(out_);
    }

private:
    ChangeTopic& Add(const std::string& key, const char* type, const char* priority, const Box& box,
                     int element, const std::string& global_id, const Rgb& color, int storey) {
        ChangeTopic t;
        t.topic.guid = NameGuid(seed_ + key);
        t.topic.type = type;
        t.topic.status = "Open";
        t.topic.priority = priority;
        t.topic.creation_date = common::FormatUtcTime(date_ns_);
        t.topic.author = "bimslam";
        t.topic.index = int(out_.size()) + 1;
        t.topic.reference_file = "model_updated.ifc";
        t.topic.labels = {type};
        t.target = box.centre();
        std::tie(t.camera, t.keyframe) = chooser_.Choose(box, element);
        BcfViewpoint& vp = t.topic.viewpoint;
        vp.guid = NameGuid(seed_ + key + "/viewpoint");
        vp.eye = t.camera.eye + model_.origin_m;  // BCF: the model's coordinates
        vp.direction = t.camera.direction;
        vp.up = t.camera.up;
        vp.fov_deg = t.camera.fov_deg;
        vp.selected = {global_id};
        vp.colors = {{Hex(color), {global_id}}};
        out_.push_back(std::move(t));
        boxes_.push_back(box);
        storeys_.push_back(storey);
        has_space_.push_back(false);
        return out_.back();
    }

    // A change of model element e, the element drawn in `color`; `to`: where a moved one went.
    ChangeTopic& AddElement(size_t e, const std::string& key, const char* type,
                            const char* priority, const Rgb& color, const changes::NewObject* to) {
        const bim::BimElement& el = model_.elements[e];
        Box box = ElementBox(model_, e);
        if (to) box.Add(to->box_min), box.Add(to->box_max);
        ChangeTopic& t = Add(key + el.global_id, type, priority, box, int(e), el.global_id, color,
                             ElementStorey(model_, e));
        t.highlight.element = int(e);
        t.highlight.element_color = color;
        return t;
    }

    static std::string What(const bim::BimElement& el) {
        return el.ifc_class + " '" + el.name + "' (" + el.global_id + ")";
    }
    std::string Where(int storey, int space) const { return WhereIn(model_, storey, space); }
    std::string Short(int storey) const {
        return storey >= 0 ? ", " + model_.storeys[size_t(storey)].name : std::string();
    }

    const bim::BimModel& model_;
    const SessionChanges& found_;
    const changes::ChangeResult& r_;
    const CameraChooser chooser_;
    const double tol_;
    const int64_t date_ns_;
    const std::string seed_;
    std::vector<ChangeTopic> out_;
    std::vector<Box> boxes_;
    std::vector<int> storeys_;
    std::vector<bool> has_space_;
};

}  // namespace

std::vector<ChangeTopic> ChangeTopics(const bim::BimModel& model, const SessionChanges& found,
                                      const changes::ChangeDetectorConfig& config,
                                      int64_t date_ns) {
    const changes::ChangeResult& r = found.result;
    TopicBuilder b(model, found, config, date_ns);
    // New objects (a moved element's object is reported with the element).
    for (size_t k = 0; k < r.objects.size(); ++k) {
        if (r.objects[k].moved_element == kNoElement) b.NewObject(k);
    }
    auto each = [&](auto pick, auto make) {
        for (size_t e = 0; e < r.elements.size(); ++e) {
            if (Physical(model.elements[e]) && pick(r.elements[e])) (b.*make)(e);
        }
    };
    using R = const changes::ElementReport&;
    each([](R rep) { return rep.verdict == changes::Verdict::kMissing; }, &TopicBuilder::Missing);
    each([](R rep) { return rep.verdict == changes::Verdict::kDeviating && !rep.moved; },
         &TopicBuilder::Deviating);
    each([](R rep) { return rep.verdict == changes::Verdict::kDeviating && rep.moved; },
         &TopicBuilder::Moved);
    return b.Finish();
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
        t.topic.viewpoint.snapshot_png = io::EncodePng(image, io::PngCompression::kFast);
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
