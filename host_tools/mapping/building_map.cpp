// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
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
#include "algorithms/io/sha256.hpp"
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
// around it (one hash lookup a cell instead of one a voxel of the neighbourhood). The cells are a
// common::VoxelHash to the newest entry of a list threaded through one vector: no allocation per
// cell (a std::unordered_map of vectors spent three quarters of a tenth visit's history step in
// its nodes and lookups).
class Buckets {
public:
    explicit Buckets(float cell, size_t expected = 1024) : cell_(cell), heads_(expected) {
        entries_.reserve(expected);
    }
    void Add(const Eigen::Vector3f& p, uint16_t first) {
        const uint32_t index = uint32_t(entries_.size());
        bool inserted = false;
        uint32_t& head = heads_.FindOrInsert(Key(Cell(p)), index, &inserted);
        entries_.push_back({p, first, inserted ? kEnd : head});
        head = index;
    }
    // Whether a point lies within r (at most the cell) of p; *earliest: the least `first` of
    // those that do (left as it is when none). Only the cells the box p +- r overlaps (two per
    // axis, not three: r is at most the cell) can hold one.
    bool Within(const Eigen::Vector3f& p, float r, uint16_t* earliest) const {
        const Eigen::Vector3f d = Eigen::Vector3f::Constant(r * 1.0001f);  // rounding aside
        const Eigen::Vector3i lo = Cell(p - d), hi = Cell(p + d);
        bool any = false;
        for (int x = lo.x(); x <= hi.x(); ++x) {
            for (int y = lo.y(); y <= hi.y(); ++y) {
                for (int z = lo.z(); z <= hi.z(); ++z) {
                    uint32_t i = heads_.Find(Key({x, y, z}));
                    for (; i != common::VoxelHash::kAbsent && i != kEnd; i = entries_[i].next) {
                        const Entry& e = entries_[i];
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
    static constexpr uint32_t kEnd = common::VoxelHash::kAbsent - 1;
    struct Entry {
        Eigen::Vector3f p;
        uint16_t first;
        uint32_t next;  // the cell's previous entry, or kEnd
    };
    Eigen::Vector3i Cell(const Eigen::Vector3f& p) const {
        return (p / cell_).array().floor().cast<int>();
    }
    static uint64_t Key(const Eigen::Vector3i& c) { return common::PackVoxel(c); }
    float cell_;
    common::VoxelHash heads_;
    std::vector<Entry> entries_;
};

}  // namespace

// The earlier visits' voxels within supersede_m of one of visit v's: that surface was seen
// again, and visit v's points are its state now. Returns how many were dropped.
size_t BuildingMap::DropSeenAgain(size_t v) {
    Buckets seen{float(supersede_m_), voxels_.size()};
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
    // This visit's points kept, one per voxel's distance; where the earlier visits saw what, and
    // since when.
    Buckets mine{float(voxel_), visit.found.map.size()};
    Buckets earlier{float(supersede_m_), voxels_.size()};
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
        e.voxel.element = p.element;
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
            const bool drop = missing.count(it->second.voxel.element) && it->second.voxel.last < v;
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
        last{"scalar_last_visit", io::PlyType::kUint16, {}},
        element{"scalar_element", io::PlyType::kInt32, {}};
    for (const Voxel& v : Voxels()) {
        ply.vertices.push_back(v.xyz);
        cls.values.push_back(v.cls);
        first.values.push_back(v.first);
        last.values.push_back(v.last);
        element.values.push_back(v.element);
    }
    ply.vertex_properties = {cls, first, last, element};
    io::WritePly(file, ply);
}

bool BuildingMap::Read(const std::filesystem::path& file) {
    const io::PlyData ply = io::ReadPly(file);
    const io::PlyProperty* cls = ply.Find("scalar_class");
    const io::PlyProperty* first = ply.Find("scalar_first_visit");
    const io::PlyProperty* last = ply.Find("scalar_last_visit");
    const io::PlyProperty* element = ply.Find("scalar_element");
    if (!cls || !first || !last || !element) return false;  // an older map: made again
    voxels_.clear();
    for (size_t i = 0; i < ply.vertices.size(); ++i) {
        Entry& e = voxels_[Key(ply.vertices[i])];
        e.voxel = {ply.vertices[i], uint8_t(cls->values[i]), uint16_t(first->values[i]),
                   uint16_t(last->values[i]), int32_t(element->values[i])};
    }
    return voxels_.size() == ply.vertices.size();
}

namespace {

// What folding visit v in depends on, as a digest chained over the visits before it: its label,
// what its findings were made from (`made_from`: the digest of its changes step's stamp, which
// changes whenever that step runs again), the boxes its history supersedes and its newly missing
// elements. Equal digests, equal fold.
std::string FoldDigest(const std::string& previous, const VisitFindings& visit, size_t v,
                       const std::string& made_from, const json& history, double voxel_m,
                       double supersede_m) {
    json superseded = json::array();
    for (const auto& [lo, hi] : SupersededBoxes(history, visit.label))
        superseded.push_back({lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z()});
    const json& since = history.at("changes").at(v).at("since_previous");
    const json inputs = {previous,   visit.label, made_from,
                         voxel_m,    supersede_m, superseded,
                         since.is_object() ? since.at("newly_missing") : json(nullptr)};
    return io::Sha256Hex(inputs.dump());
}

// How many of the visits the map on disk has folded in already, as this run would (their fold
// digests equal), with their figures; 0 when none can be kept (no map, another layout, a visit
// added before the last, a visit's changes or history made again).
size_t FoldedAlready(const std::filesystem::path& out, const std::vector<std::string>& digests,
                     BuildingMap* map, json* figures) {
    const std::filesystem::path file = out / "building_map.json";
    if (!std::filesystem::exists(file) || !std::filesystem::exists(out / "building_map.ply"))
        return 0;
    json old;
    try {
        old = json::parse(io::ReadFileToString(file));
    } catch (const json::exception&) {
        return 0;  // damaged: made again from the visits
    }
    if (old.value("version", 0) != 2 || old.value("voxel_m", 0.0) != map->voxel_m()) return 0;
    const json& visits = old.at("visits");
    if (visits.size() > digests.size()) return 0;
    for (size_t v = 0; v < visits.size(); ++v) {
        if (visits[v].value("fold_sha256", "") != digests[v]) return 0;
    }
    if (!map->Read(out / "building_map.ply")) return 0;
    *figures = visits;
    return visits.size();
}

}  // namespace

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
                      const json& history, const std::vector<std::string>& made_from) {
    BuildingMap map;
    std::vector<std::string> digests;
    for (size_t v = 0; v < visits.size(); ++v) {
        digests.push_back(FoldDigest(v ? digests.back() : "", visits[v], v, made_from.at(v),
                                     history, map.voxel_m(), map.supersede_m()));
    }
    // A visit added after the others folds in that visit alone: the cost of adding the tenth
    // visit is that of one fold, not ten (issue 33's target).
    json figures = json::array();
    for (size_t v = FoldedAlready(out, digests, &map, &figures); v < visits.size(); ++v) {
        figures.push_back(map.Add(v, visits[v], history));
        figures.back()["fold_sha256"] = digests[v];
    }
    map.Write(out / "building_map.ply");
    std::vector<int64_t> starts;
    for (const VisitFindings& v : visits) starts.push_back(v.start_ns);
    map.WriteLas(out / "building_map.las", starts);
    const json j = {
        {"format", "bimslam-building-map"}, {"version", 2},         {"file", "building_map.ply"},
        {"voxel_m", map.voxel_m()},         {"voxels", map.size()}, {"visits", figures}};
    io::WriteFileAtomic(out / "building_map.json", j.dump(1) + "\n");
    return j;
}

}  // namespace bimslam::mapping
