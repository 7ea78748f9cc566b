#include "host_tools/mapping/building_map.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "algorithms/changes/change_detector.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/ply.hpp"

namespace bimslam::mapping {
using nlohmann::json;

namespace {

Eigen::Vector3d Vec3(const json& j) {
    return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

// The box of a sighting that placed an object (its centroid and size).
bool PlacedBox(const json& s, Eigen::Vector3d* lo, Eigen::Vector3d* hi) {
    if (!s.contains("centroid")) return false;
    const Eigen::Vector3d c = Vec3(s.at("centroid")), half = 0.5 * Vec3(s.at("size_m"));
    *lo = c - half;
    *hi = c + half;
    return true;
}

// Where the objects gone or moved at visit `label` stood before it: their last placed sighting
// before that visit.
std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> SupersededBoxes(const json& history,
                                                                         const std::string& label) {
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> boxes;
    for (const json& o : history.at("objects")) {
        Eigen::Vector3d lo, hi;
        bool placed = false;
        for (const json& s : o.at("sightings")) {
            if (s.at("visit") == label) {
                const std::string status = s.at("status");
                if (placed && (status == "gone" || status == "moved")) boxes.emplace_back(lo, hi);
                break;
            }
            placed = PlacedBox(s, &lo, &hi) || placed;
        }
    }
    return boxes;
}

}  // namespace

uint64_t BuildingMap::Key(const Eigen::Vector3f& p) const {
    const auto bits = [&](float v) {  // 21 bits an axis: +-52 km at 5 cm
        return uint64_t(uint32_t(int32_t(std::floor(double(v) / voxel_))) & 0x1FFFFFu);
    };
    return (bits(p.x()) << 42) | (bits(p.y()) << 21) | bits(p.z());
}

// The voxel of visit v within one voxel of p, nearest first: the visit's own points are kept
// one per voxel's distance (its recordings, and the 5 cm voxels of one map, overlap).
std::optional<BuildingMap::Map::iterator> BuildingMap::Near(const Eigen::Vector3f& p, size_t v,
                                                            int cells, float radius) {
    std::optional<Map::iterator> best;
    float best_d2 = radius * radius;
    for (int dx = -cells; dx <= cells; ++dx) {
        for (int dy = -cells; dy <= cells; ++dy) {
            for (int dz = -cells; dz <= cells; ++dz) {
                const Eigen::Vector3f q = p + Eigen::Vector3f(dx, dy, dz) * float(voxel_);
                const auto it = voxels_.find(Key(q));
                if (it == voxels_.end() || it->second.voxel.last != v) continue;
                const float d2 = (it->second.voxel.xyz - p).squaredNorm();
                if (d2 < best_d2) {
                    best_d2 = d2;
                    best = it;
                }
            }
        }
    }
    return best;
}

// The first visit of the earlier visits' voxels within supersede_m of p (v when none).
uint16_t BuildingMap::EarliestNear(const Eigen::Vector3f& p, size_t v) const {
    const int cells = int(std::ceil(supersede_m_ / voxel_));
    const float r2 = float(supersede_m_ * supersede_m_);
    uint16_t first = uint16_t(v);
    for (int dx = -cells; dx <= cells; ++dx) {
        for (int dy = -cells; dy <= cells; ++dy) {
            for (int dz = -cells; dz <= cells; ++dz) {
                const auto it =
                    voxels_.find(Key(p + Eigen::Vector3f(dx, dy, dz) * float(voxel_)));
                if (it == voxels_.end() || it->second.voxel.last == v) continue;
                if ((it->second.voxel.xyz - p).squaredNorm() < r2)
                    first = std::min(first, it->second.voxel.first);
            }
        }
    }
    return first;
}

// The earlier visits' voxels within supersede_m of one of visit v's: that surface was seen
// again, and visit v's points are its state now. Returns how many were dropped.
size_t BuildingMap::DropSeenAgain(size_t v) {
    const int cells = int(std::ceil(supersede_m_ / voxel_));
    std::vector<uint64_t> drop;
    for (auto& [key, e] : voxels_) {
        if (e.voxel.last == v) continue;
        const auto seen = Near(e.voxel.xyz, v, cells, float(supersede_m_));
        if (!seen) continue;
        drop.push_back(key);
    }
    for (const uint64_t key : drop) voxels_.erase(key);
    return drop.size();
}

size_t BuildingMap::DropInBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, size_t before) {
    size_t dropped = 0;
    for (auto it = voxels_.begin(); it != voxels_.end();) {
        const Eigen::Vector3d p = it->second.voxel.xyz.cast<double>();
        const bool inside = (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
        if (inside && it->second.voxel.last < before) {
            it = voxels_.erase(it);
            ++dropped;
        } else {
            ++it;
        }
    }
    return dropped;
}

json BuildingMap::Add(size_t v, const VisitFindings& visit, const json& history) {
    size_t kept = 0, transient = 0;
    const size_t old = voxels_.size();
    for (const auto& p : visit.found.map) {
        if (p.cls == uint8_t(changes::PointClass::kTransient)) {
            ++transient;
            continue;
        }
        if (Near(p.xyz, v, 1, float(voxel_))) continue;  // kept already, of this visit
        auto [it, inserted] = voxels_.try_emplace(Key(p.xyz));
        Entry& e = it->second;
        // A surface seen again keeps the visit that first saw it (the earliest within reach).
        e.voxel.first = std::min(inserted ? uint16_t(v) : e.voxel.first, EarliestNear(p.xyz, v));
        e.voxel.xyz = p.xyz;
        e.voxel.cls = p.cls;
        e.voxel.last = uint16_t(v);
        e.element = p.element;
        ++kept;
    }
    const size_t seen_again = DropSeenAgain(v);
    // What this visit's history supersedes: voxels it did not see again in those places.
    size_t objects = 0, elements = 0;
    const Eigen::Vector3d margin = Eigen::Vector3d::Constant(voxel_);
    for (const auto& [lo, hi] : SupersededBoxes(history, visit.label))
        objects += DropInBox(lo - margin, hi + margin, v);
    const json& since = history.at("changes").at(v).at("since_previous");
    if (since.is_object()) {
        for (const json& id : since.at("newly_missing")) {
            const auto e = visit.found.elements.find(id.get<std::string>());
            if (e == visit.found.elements.end() || e->second.index < 0) continue;
            for (auto it = voxels_.begin(); it != voxels_.end();) {
                const bool drop =
                    it->second.element == e->second.index && it->second.voxel.last < v;
                elements += drop;
                it = drop ? voxels_.erase(it) : std::next(it);
            }
        }
    }
    return {{"visit", visit.label},
            {"voxels", voxels_.size()},
            {"growth", old ? json(double(voxels_.size()) / double(old) - 1.0) : json(nullptr)},
            {"points", kept},
            {"dropped",
             {{"seen_again", seen_again},
              {"superseded_objects", objects},
              {"missing_elements", elements}}},
            {"transient_points", transient}};
}

std::vector<BuildingMap::Voxel> BuildingMap::Voxels() const {
    std::vector<std::pair<uint64_t, Voxel>> keyed;
    keyed.reserve(voxels_.size());
    for (const auto& [k, e] : voxels_) keyed.emplace_back(k, e.voxel);
    std::sort(keyed.begin(), keyed.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<Voxel> out;
    out.reserve(keyed.size());
    for (const auto& [k, voxel] : keyed) out.push_back(voxel);
    return out;
}

void BuildingMap::Write(const std::filesystem::path& file) const {
    io::PlyData ply;
    io::PlyProperty cls{"scalar_class", io::PlyType::kUint8, {}},
        first{"scalar_first_visit", io::PlyType::kUint16, {}},
        last{"scalar_last_visit", io::PlyType::kUint16, {}};
    for (const Voxel& v : Voxels()) {
        ply.vertices.push_back(v.xyz);
        cls.values.push_back(v.cls);
        first.values.push_back(v.first);
        last.values.push_back(v.last);
    }
    ply.vertex_properties = {cls, first, last};
    io::WritePly(file, ply);
}

json WriteBuildingMap(const std::filesystem::path& out, const std::vector<VisitFindings>& visits,
                      const json& history) {
    BuildingMap map;
    json figures = json::array();
    for (size_t v = 0; v < visits.size(); ++v) figures.push_back(map.Add(v, visits[v], history));
    map.Write(out / "building_map.ply");
    const json j = {{"format", "bimslam-building-map"},
                    {"version", 1},
                    {"file", "building_map.ply"},
                    {"voxel_m", 0.05},
                    {"voxels", map.size()},
                    {"visits", figures}};
    io::WriteFileAtomic(out / "building_map.json", j.dump(1) + "\n");
    return j;
}

}  // namespace bimslam::mapping
