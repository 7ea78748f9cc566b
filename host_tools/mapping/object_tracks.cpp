// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/mapping/object_tracks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>
#include <unordered_set>

#include "algorithms/common/voxel_hash.hpp"

namespace bimslam::mapping {
using Box = Eigen::AlignedBox3d;
using change_detection::FoundChanges;
using nlohmann::json;

json Vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

namespace {

double Iou(const Box& a, const Box& b) {
    const Box i = a.intersection(b);
    if (i.isEmpty()) return 0.0;
    const double vi = i.volume();
    return vi / (a.volume() + b.volume() - vi);
}

// The cells (cell_m) of a visit's map: what its keyframes saw.
class SeenCells {
public:
    SeenCells(const std::vector<FoundChanges::MapPoint>& map, double cell_m) : cell_(cell_m) {
        cells_.reserve(map.size());
        for (const auto& p : map) cells_.insert(Key(Cell(p.xyz.cast<double>())));
    }

    // The share of `box`'s footprint cells (wholly inside it in plan, and not under any box of
    // `cover` standing on the same floor) with a map point within `band` of its bottom; *cells:
    // how many were judged.
    double FloorSeen(const Box& object_box, const std::vector<Box>& cover, double band,
                     size_t* cells) const {
        // A thin box (a partition, or a face seen alone: a shelf's front, 7 cm deep) holds no
        // whole cell across: it is judged as two cells wide about its middle.
        Box box = object_box;
        for (int axis = 0; axis < 2; ++axis) {
            if (box.sizes()[axis] >= 2 * cell_) continue;
            const double c = box.center()[axis];
            box.min()[axis] = c - cell_;
            box.max()[axis] = c + cell_;
        }
        const Eigen::Vector3i lo = Cell(box.min()), hi = Cell(box.max());
        const int z0 = Cell(box.min() - Eigen::Vector3d(0, 0, band)).z();
        const int z1 = Cell(box.min() + Eigen::Vector3d(0, 0, band)).z();
        size_t judged = 0, seen = 0;
        for (int x = lo.x(); x <= hi.x(); ++x) {
            for (int y = lo.y(); y <= hi.y(); ++y) {
                const Eigen::Vector2d c((x + 0.5) * cell_, (y + 0.5) * cell_);
                const Eigen::Vector2d half(0.5 * cell_, 0.5 * cell_);
                if (!InPlan(box, c - half) || !InPlan(box, c + half)) continue;
                const bool covered = std::any_of(cover.begin(), cover.end(), [&](const Box& b) {
                    return InPlan(b, c) && std::abs(b.min().z() - box.min().z()) < 0.5;
                });
                if (covered) continue;
                ++judged;
                for (int z = z0; z <= z1; ++z) {
                    if (cells_.count(Key({x, y, z}))) {
                        ++seen;
                        break;
                    }
                }
            }
        }
        *cells = judged;
        return judged ? double(seen) / double(judged) : 0.0;
    }

private:
    static bool InPlan(const Box& b, const Eigen::Vector2d& c) {
        return c.x() >= b.min().x() && c.x() <= b.max().x() && c.y() >= b.min().y() &&
               c.y() <= b.max().y();
    }
    Eigen::Vector3i Cell(const Eigen::Vector3d& p) const {
        return (p / cell_).array().floor().cast<int>();
    }
    static uint64_t Key(const Eigen::Vector3i& c) { return common::PackVoxel(c); }

    double cell_;
    std::unordered_set<uint64_t> cells_;
};

// Greedy one-to-one: the pairs in the order given, each track and object used once.
template <typename Pair>
std::vector<std::pair<size_t, size_t>> OneToOne(const std::vector<Pair>& sorted) {
    std::unordered_set<size_t> tracks, objects;
    std::vector<std::pair<size_t, size_t>> out;
    for (const Pair& p : sorted) {
        const size_t t = std::get<1>(p), o = std::get<2>(p);
        if (tracks.count(t) || objects.count(o)) continue;
        tracks.insert(t);
        objects.insert(o);
        out.emplace_back(t, o);
    }
    return out;
}

// A sighting of visit v's object o: where, and which recording's changes found it (its mesh).
json Placed(const VisitFindings& visit, size_t o, const char* status) {
    const FoundChanges::Object& object = visit.found.objects[o];
    return {{"visit", visit.label},
            {"status", status},
            {"centroid", Vec(object.box.center())},
            {"size_m", Vec(object.box.sizes())},
            {"recording", o < visit.object_recordings.size() ? visit.object_recordings[o] : ""},
            {"object", object.id},
            {"ifc_global_id", object.ifc_global_id}};
}

}  // namespace

bool SamePlace(const Box& a, const Box& b, const HistoryConfig& config) {
    return Iou(a, b) >= config.same_min_iou ||
           (a.center() - b.center()).norm() <= config.same_max_centroid_m;
}

double InsideShare(const Box& a, const Box& b, double margin_m) {
    const double va = a.volume();
    if (a.isEmpty() || va <= 0) return 0.0;
    Box grown = b;
    grown.min().array() -= margin_m;
    grown.max().array() += margin_m;
    const Box i = a.intersection(grown);
    return i.isEmpty() ? 0.0 : i.volume() / va;
}

namespace {

bool Close(double x, double y, double relative, const HistoryConfig& config) {
    return std::abs(x - y) <= std::max(config.shape_tolerance_m, relative * std::max(x, y));
}

// Where an object stands: its plan rectangle's centre (changes.json's plan_center_m), which a
// turned object seen without a corner keeps, its box's in older files; its box's height.
Eigen::Vector3d Centre(const FoundChanges::Object& o) {
    Eigen::Vector3d c = o.box.center();
    if (o.plan_center) c.head<2>() = *o.plan_center;
    return c;
}

// The height and the plan's sides agree: the smallest rectangles', which a turn leaves as they
// are (files without them: the boxes' sorted sides).
bool SameSides(const FoundChanges::Object& a, const FoundChanges::Object& b,
               const HistoryConfig& config) {
    const Eigen::Vector3d sa = a.box.sizes(), sb = b.box.sizes();
    if (!Close(sa.z(), sb.z(), config.shape_tolerance, config)) return false;
    const auto sides = [](const FoundChanges::Object& o, const Eigen::Vector3d& s) {
        return o.plan_long_m > 0 ? Eigen::Vector2d(o.plan_long_m, o.plan_short_m)
                                 : Eigen::Vector2d(std::max(s.x(), s.y()), std::min(s.x(), s.y()));
    };
    const Eigen::Vector2d pa = sides(a, sa), pb = sides(b, sb);
    return Close(pa.x(), pb.x(), config.shape_tolerance, config) &&
           Close(pa.y(), pb.y(), config.shape_tolerance, config);
}

}  // namespace

bool SameShape(const FoundChanges::Object& a, const FoundChanges::Object& b,
               const HistoryConfig& config) {
    if (!Close(a.box.sizes().z(), b.box.sizes().z(), config.shape_tolerance, config)) return false;
    const bool volume = a.volume_m3 > 0 && b.volume_m3 > 0 &&
                        std::abs(a.volume_m3 - b.volume_m3) <=
                            config.volume_tolerance * std::max(a.volume_m3, b.volume_m3);
    return SameSides(a, b, config) || volume;
}

bool Displaced(const FoundChanges::Object& a, const FoundChanges::Object& b,
               const HistoryConfig& config) {
    return SameSides(a, b, config) && (Centre(a) - Centre(b)).norm() > config.same_max_centroid_m;
}

std::vector<size_t> ObjectTracks::Alive() const {
    std::vector<size_t> alive;
    for (size_t t = 0; t < tracks_.size(); ++t) {
        if (!tracks_[t].gone) alive.push_back(t);
    }
    return alive;
}

// The same objects in place: the best IoU first, then the nearest centres.
ObjectTracks::Pairs ObjectTracks::InPlace(const std::vector<size_t>& alive,
                                          const VisitFindings& visit) const {
    std::vector<std::tuple<double, size_t, size_t>> pairs;  // (-IoU - closeness, track, object)
    const auto& objects = visit.found.objects;
    for (const size_t t : alive) {
        for (size_t o = 0; o < objects.size(); ++o) {
            const Box &a = tracks_[t].last.box, &b = objects[o].box;
            if (!SamePlace(a, b, config_) || Displaced(tracks_[t].last, objects[o], config_))
                continue;
            const double distance = (a.center() - b.center()).norm();
            pairs.emplace_back(-Iou(a, b) + 1e-3 * distance, t, o);
        }
    }
    std::sort(pairs.begin(), pairs.end());
    return OneToOne(pairs);
}

// The best-containing track of each unmatched object (the largest share inside, then the nearest
// centre).
ObjectTracks::Pairs ObjectTracks::Parts(const std::vector<size_t>& alive,
                                        const VisitFindings& visit,
                                        const std::vector<bool>& object_done) const {
    Pairs parts;
    const auto& objects = visit.found.objects;
    for (size_t o = 0; o < objects.size(); ++o) {
        if (object_done[o]) continue;
        std::optional<std::pair<double, size_t>> best;  // (-share + closeness, track)
        for (const size_t t : alive) {
            const Box& known = tracks_[t].last.box;
            if (Displaced(tracks_[t].last, objects[o], config_)) continue;  // moved, not a part
            const double share = InsideShare(objects[o].box, known, config_.part_margin_m);
            if (share < config_.part_min_inside) continue;
            const double key = -share + 1e-3 * (known.center() - objects[o].box.center()).norm();
            if (!best || key < best->first) best = {key, t};
        }
        if (best) parts.emplace_back(best->second, o);
    }
    return parts;
}

// Moved objects: of the same shape and storey, within reach, whose old place was seen empty;
// the nearest first.
ObjectTracks::Pairs ObjectTracks::Moved(const std::vector<size_t>& tracks,
                                        const std::vector<size_t>& objects,
                                        const VisitFindings& visit,
                                        const std::vector<double>& seen_empty) const {
    std::vector<std::tuple<double, size_t, size_t>> pairs;
    for (const size_t t : tracks) {
        const bool left = seen_empty[t] >= config_.min_floor_seen;
        for (const size_t o : objects) {
            const FoundChanges::Object& object = visit.found.objects[o];
            const Track& track = tracks_[t];
            // An object of its shape standing partly where it stood is it, moved: two solids
            // cannot share that space, so its old place needs no floor seen empty.
            if (!left &&
                !(Displaced(track.last, object, config_) && Iou(track.last.box, object.box) > 0)) {
                continue;
            }
            const double distance = (object.box.center() - track.last.box.center()).norm();
            const bool same_storey =
                track.storey.empty() || object.storey.empty() || track.storey == object.storey;
            if (distance <= config_.moved_max_m && same_storey &&
                SameShape(track.last, object, config_)) {
                pairs.emplace_back(distance, t, o);
            }
        }
    }
    std::sort(pairs.begin(), pairs.end());
    return OneToOne(pairs);
}

json ObjectTracks::Update(size_t v, const VisitFindings& visit) {
    const auto& objects = visit.found.objects;
    const std::string& label = visit.label;
    std::vector<bool> track_done(tracks_.size(), false), object_done(objects.size(), false);
    json added = json::array(), gone = json::array(), moved = json::array();
    const std::vector<size_t> alive = Alive();
    for (const auto& [t, o] : InPlace(alive, visit)) {
        tracks_[t].last = objects[o];
        tracks_[t].last_seen = v;
        tracks_[t].sightings.push_back(Placed(visit, o, "seen"));
        track_done[t] = object_done[o] = true;
    }
    for (const auto& [t, o] : Parts(alive, visit, object_done)) {
        if (!track_done[t]) {
            // A part only: the object stands where it is known to (its box kept, the sighting's
            // place); the part found is said beside it.
            json s = Placed(visit, o, "seen");
            s["part"] = {{"centroid", s["centroid"]}, {"size_m", s["size_m"]}};
            s["centroid"] = Vec(tracks_[t].last.box.center());
            s["size_m"] = Vec(tracks_[t].last.box.sizes());
            tracks_[t].sightings.push_back(s);
            tracks_[t].last_seen = v;
        }
        track_done[t] = object_done[o] = true;
    }
    // Where the tracks left unmatched stood: seen empty, or not judged (-1).
    const SeenCells seen(visit.found.map, config_.cell_m);
    std::vector<Box> cover;
    for (const auto& o : objects) cover.push_back(o.box);
    std::vector<double> seen_empty(tracks_.size(), -1.0);
    std::vector<size_t> open_tracks, open_objects;
    for (const size_t t : alive) {
        if (track_done[t]) continue;
        size_t cells = 0;
        const double share =
            seen.FloorSeen(tracks_[t].last.box, cover, config_.floor_band_m, &cells);
        if (cells >= config_.min_cells) seen_empty[t] = share;
        open_tracks.push_back(t);
    }
    for (size_t o = 0; o < objects.size(); ++o) {
        if (!object_done[o]) open_objects.push_back(o);
    }
    for (const auto& [t, o] : Moved(open_tracks, open_objects, visit, seen_empty)) {
        const Eigen::Vector3d offset = Centre(objects[o]) - Centre(tracks_[t].last);
        json s = Placed(visit, o, "moved");
        s["offset_m"] = Vec(offset);
        tracks_[t].sightings.push_back(s);
        tracks_[t].last = objects[o];
        tracks_[t].last_seen = v;
        moved.push_back({{"id", tracks_[t].id}, {"offset_m", Vec(offset)}});
        track_done[t] = object_done[o] = true;
    }
    for (const size_t t : open_tracks) {
        if (track_done[t]) continue;
        const bool empty = seen_empty[t] >= config_.min_floor_seen;
        tracks_[t].sightings.push_back(
            {{"visit", label},
             {"status", empty ? "gone" : "not_observed"},
             {"floor_seen", seen_empty[t] < 0 ? json(nullptr) : json(seen_empty[t])}});
        if (!empty) continue;
        tracks_[t].gone = v;
        gone.push_back(tracks_[t].id);
    }
    for (size_t o = 0; o < objects.size(); ++o) {
        if (object_done[o]) continue;
        Track t{"O" + std::to_string(tracks_.size() + 1),
                objects[o],
                objects[o].storey,
                v,
                v,
                std::nullopt,
                json::array()};
        t.sightings.push_back(Placed(visit, o, "new"));
        added.push_back(t.id);
        tracks_.push_back(std::move(t));
    }
    return {{"new", added}, {"gone", gone}, {"moved", moved}};
}

json ObjectTracks::Present(const std::vector<VisitFindings>& visits) const {
    json present = json::array();
    for (const Track& t : tracks_) {
        if (!t.gone) present.push_back({{"id", t.id}, {"as_of", visits[t.last_seen].label}});
    }
    return present;
}

json ObjectTracks::ToJson(const std::vector<VisitFindings>& visits) const {
    json out = json::array();
    for (const Track& t : tracks_) {
        out.push_back({{"id", t.id},
                       {"storey", t.storey},
                       {"first_seen", visits[t.first_seen].label},
                       {"last_seen", visits[t.last_seen].label},
                       {"state", t.gone ? "gone" : "present"},
                       {"gone_in", t.gone ? json(visits[*t.gone].label) : json(nullptr)},
                       {"box_min", Vec(t.last.box.min())},
                       {"box_max", Vec(t.last.box.max())},
                       {"sightings", t.sightings}});
    }
    return out;
}

}  // namespace bimslam::mapping
