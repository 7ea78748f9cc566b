#include "host_tools/mapping/building_map.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <unordered_set>

#include "algorithms/changes/change_detector.hpp"
#include "algorithms/common/voxel_hash.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/las.hpp"
#include "algorithms/io/ply.hpp"
#include "host_tools/changes/map_las.hpp"

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
    const auto index = [&](float v) { return int(std::floor(double(v) / voxel_)); };
    return common::PackVoxel({index(p.x()), index(p.y()), index(p.z())});
}

namespace {

// Points in cells of `cell` metres: what lies within `cell` of a point is in the 27 cells
// around it (one hash lookup a cell instead of one a voxel of the neighbourhood).
class Buckets {
public:
    explicit Buckets(float cell) : cell_(cell) {}
    void Add(const Eigen::Vector3f& p, uint16_t first) {
        cells_[Key(Cell(p))].push_back({p, first});
    }
    // Whether a point lies within r (at most the cell) of p; *earliest: the least `first` of
    // those that do (left as it is when none).
    bool Within(const Eigen::Vector3f& p, float r, uint16_t* earliest) const {
        const Eigen::Vector3i c = Cell(p);
        bool any = false;
        for (int dx = -1; dx <= 1; ++dx) {
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dz = -1; dz <= 1; ++dz) {
                    const auto it = cells_.find(Key(c + Eigen::Vector3i(dx, dy, dz)));
                    if (it == cells_.end()) continue;
                    for (const Entry& e : it->second) {
                        if ((e.p - p).squaredNorm() >= r * r) continue;
                        if (!earliest) return true;
                        any = true;
                        *earliest = std::min(*earliest, e.first);
                    }
                }
            }
        }
        return any;
    }

private:
    struct Entry {
        Eigen::Vector3f p;
        uint16_t first;
    };
    Eigen::Vector3i Cell(const Eigen::Vector3f& p) const {
        return (p / cell_).array().floor().cast<int>();
    }
    static uint64_t Key(const Eigen::Vector3i& c) { return common::PackVoxel(c); }
    float cell_;
    std::unordered_map<uint64_t, std::vector<Entry>> cells_;
};

}  // namespace

// The earlier visits' voxels within supersede_m of one of visit v's: that surface was seen
// again, and visit v's points are its state now. Returns how many were dropped.
size_t BuildingMap::DropSeenAgain(size_t v) {
    Buckets seen{float(supersede_m_)};
    for (const auto& [key, e] : voxels_) {
        if (e.voxel.last == v) seen.Add(e.voxel.xyz, e.voxel.first);
    }
    std::vector<uint64_t> drop;
    for (const auto& [key, e] : voxels_) {
        if (e.voxel.last != v && seen.Within(e.voxel.xyz, float(supersede_m_), nullptr))
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
    Buckets mine{float(voxel_)};           // this visit's points kept, one per voxel's distance
    Buckets earlier{float(supersede_m_)};  // where the earlier visits saw what, and since when
    for (const auto& [key, e] : voxels_) earlier.Add(e.voxel.xyz, e.voxel.first);
    for (const auto& p : visit.found.map) {
        if (p.cls == uint8_t(changes::PointClass::kTransient)) {
            ++transient;
            continue;
        }
        if (mine.Within(p.xyz, float(voxel_), nullptr)) continue;  // kept already, of this visit
        mine.Add(p.xyz, 0);
        auto [it, inserted] = voxels_.try_emplace(Key(p.xyz));
        Entry& e = it->second;
        // A surface seen again keeps the visit that first saw it (the earliest within reach).
        e.voxel.first = inserted ? uint16_t(v) : e.voxel.first;
        earlier.Within(p.xyz, float(supersede_m_), &e.voxel.first);
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
    std::unordered_set<int32_t> missing;  // the newly missing elements' indices
    if (since.is_object()) {
        for (const json& id : since.at("newly_missing")) {
            const auto e = visit.found.elements.find(id.get<std::string>());
            if (e != visit.found.elements.end() && e->second.index >= 0)
                missing.insert(e->second.index);
        }
    }
    if (!missing.empty()) {  // one pass over the map for all of them
        for (auto it = voxels_.begin(); it != voxels_.end();) {
            const bool drop = missing.count(it->second.element) && it->second.voxel.last < v;
            elements += drop;
            it = drop ? voxels_.erase(it) : std::next(it);
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

void BuildingMap::WriteLas(const std::filesystem::path& file,
                           const std::vector<int64_t>& visit_start_ns) const {
    io::LasData las;
    io::SetLasCreationDate(las, std::chrono::duration_cast<std::chrono::nanoseconds>(
                                    std::chrono::system_clock::now().time_since_epoch())
                                    .count());
    io::LasExtraField first{"first_visit", io::LasType::kUint16, "visit that first saw it", {}, {}};
    for (const Voxel& v : Voxels()) {
        las.xyz.push_back(v.xyz.cast<double>());
        las.classification.push_back(change_detection::LasClass(changes::PointClass(v.cls)));
        las.user_data.push_back(v.cls);
        las.point_source_id.push_back(uint16_t(v.last + 1));
        las.gps_time.push_back(io::UnixNsToAdjustedGpsSeconds(visit_start_ns.at(v.last)));
        first.values.push_back(v.first + 1);
    }
    las.extra = {std::move(first)};
    io::WriteLas(file, las);
}

json WriteBuildingMap(const std::filesystem::path& out, const std::vector<VisitFindings>& visits,
                      const json& history) {
    BuildingMap map;
    json figures = json::array();
    for (size_t v = 0; v < visits.size(); ++v) figures.push_back(map.Add(v, visits[v], history));
    map.Write(out / "building_map.ply");
    std::vector<int64_t> starts;
    for (const VisitFindings& v : visits) starts.push_back(v.start_ns);
    map.WriteLas(out / "building_map.las", starts);
    const json j = {
        {"format", "bimslam-building-map"}, {"version", 1},         {"file", "building_map.ply"},
        {"voxel_m", map.voxel_m()},         {"voxels", map.size()}, {"visits", figures}};
    io::WriteFileAtomic(out / "building_map.json", j.dump(1) + "\n");
    return j;
}

}  // namespace bimslam::mapping
