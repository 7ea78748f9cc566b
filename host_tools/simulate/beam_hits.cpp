#include "host_tools/simulate/beam_hits.hpp"

#include <nlohmann/json.hpp>

namespace bimslam::simulate {

BeamHitCounter::BeamHitCounter(const bim::BimModel& model, const World& world)
    : added_hits_(world.added.size(), 0) {
    common::TriangleMesh removed;
    std::vector<uint32_t> ids;
    for (const ElementChange& c : world.changes) {
        for (size_t e = 0; e < model.elements.size(); ++e) {
            const bim::BimElement& el = model.elements[e];
            if (el.global_id != c.global_id) continue;
            element_ids_[uint32_t(e)] = c.global_id;
            element_hits_[uint32_t(e)] = 0;
            if (c.change != "removed") break;
            for (uint32_t t = el.first_triangle; t < el.first_triangle + el.triangle_count; ++t) {
                const auto base = uint32_t(removed.vertices.size());
                for (const uint32_t v : model.mesh.triangles[t]) {
                    removed.vertices.push_back(model.mesh.vertices[v]);
                }
                removed.triangles.push_back({base, base + 1, base + 2});
                ids.push_back(uint32_t(e));
            }
            break;
        }
    }
    if (!removed.triangles.empty()) {
        removed_ = std::make_unique<simulation::Scene>(removed, std::move(ids));
    }
}

void BeamHitCounter::Count(const simulation::LidarModel& lidar,
                           std::span<const Eigen::Isometry3d> poses,
                           const simulation::ScanImage& image) {
    for (size_t i = 0; i < image.element_id.size(); ++i) {
        if (image.range_mm[i] == 0) continue;
        const uint32_t id = image.element_id[i];
        if (id >= kAddedIdBase && id - kAddedIdBase < added_hits_.size()) {
            ++added_hits_[id - kAddedIdBase];
        } else if (auto it = element_hits_.find(id); it != element_hits_.end()) {
            ++it->second;
        }
    }
    if (!removed_) return;
    simulation::SimulateScan(*removed_, lidar, poses, simulation::NoiseModel::Noiseless(), 0,
                             &removed_image_);
    for (size_t i = 0; i < removed_image_.range_mm.size(); ++i) {
        const uint32_t r = removed_image_.range_mm[i];
        if (r == 0 || (image.range_mm[i] != 0 && image.range_mm[i] <= r)) continue;
        if (auto it = element_hits_.find(removed_image_.element_id[i]); it != element_hits_.end()) {
            ++it->second;
        }
    }
}

size_t BeamHitCounter::HitsOfAdded(size_t k) const { return added_hits_.at(k); }

size_t BeamHitCounter::HitsOfElement(const std::string& global_id) const {
    for (const auto& [e, id] : element_ids_) {
        if (id == global_id) return element_hits_.at(e);
    }
    return 0;
}

void BeamHitCounter::AddTo(nlohmann::json& changes) const {
    for (size_t k = 0; k < changes["added"].size() && k < added_hits_.size(); ++k) {
        changes["added"][k]["beam_hits"] = added_hits_[k];
    }
    for (const char* list : {"removed", "moved"}) {
        for (nlohmann::json& e : changes[list]) {
            e["beam_hits"] = HitsOfElement(e["global_id"].get<std::string>());
        }
    }
}

}  // namespace bimslam::simulate
