// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/simulate/beam_hits.hpp"

#include <nlohmann/json.hpp>

namespace bimslam::simulate {

namespace {

// Every beam of `image` whose cast in `scene` (noiseless) hits before what the beam did hit (or
// where it had no return): `count(id)` with the id of what it would have hit.
template <typename F>
void CountWouldHaveHit(const simulation::Scene& scene, const simulation::LidarModel& lidar,
                       std::span<const Eigen::Isometry3d> poses, const simulation::ScanImage& image,
                       simulation::ScanImage& cast, F&& count) {
    simulation::SimulateScan(scene, lidar, poses, simulation::NoiseModel::Noiseless(), 0, &cast);
    for (size_t i = 0; i < cast.range_mm.size(); ++i) {
        const uint32_t r = cast.range_mm[i];
        if (r == 0 || (image.range_mm[i] != 0 && image.range_mm[i] <= r)) continue;
        count(cast.element_id[i]);
    }
}

}  // namespace

BeamHitCounter::BeamHitCounter(const bim::BimModel& model, const World& world,
                               const HitWatch& watch)
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
    for (const std::string& id : watch.elements) {
        for (size_t e = 0; e < model.elements.size(); ++e) {
            if (model.elements[e].global_id != id) continue;
            element_ids_.emplace(uint32_t(e), id);
            element_hits_.emplace(uint32_t(e), 0);
            watched_elements_.push_back(id);
            break;
        }
    }
    common::TriangleMesh absent;
    std::vector<uint32_t> absent_ids;
    for (const auto& [key, mesh] : watch.absent) {
        const auto base = uint32_t(absent.vertices.size());
        absent.vertices.insert(absent.vertices.end(), mesh.vertices.begin(), mesh.vertices.end());
        for (const auto& t : mesh.triangles) {
            absent.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
            absent_ids.push_back(uint32_t(absent_keys_.size()));
        }
        absent_keys_.push_back(key);
    }
    absent_hits_.assign(absent_keys_.size(), 0);
    if (!absent.triangles.empty()) {
        absent_ = std::make_unique<simulation::Scene>(absent, std::move(absent_ids));
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
    if (removed_) {
        CountWouldHaveHit(*removed_, lidar, poses, image, removed_image_, [&](uint32_t id) {
            if (auto it = element_hits_.find(id); it != element_hits_.end()) ++it->second;
        });
    }
    if (absent_) {
        CountWouldHaveHit(*absent_, lidar, poses, image, removed_image_,
                          [&](uint32_t id) { ++absent_hits_.at(id); });
    }
}

std::map<std::string, size_t> BeamHitCounter::Watched() const {
    std::map<std::string, size_t> out;
    for (size_t k = 0; k < absent_keys_.size(); ++k) out[absent_keys_[k]] = absent_hits_[k];
    for (const std::string& id : watched_elements_) out[id] = HitsOfElement(id);
    return out;
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
