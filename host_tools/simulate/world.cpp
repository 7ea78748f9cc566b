// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/simulate/world.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <set>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/ply.hpp"
#include "algorithms/simulation/primitive_meshes.hpp"

namespace bimslam::simulate {
namespace {
using common::StatusCode;
constexpr double kGroundWidthM = 40.0;
constexpr double kClutterGapM = 0.05;  // clutter's least gap to walls and to other objects

[[noreturn]] void Fail(const std::string& what) {
    throw common::Error(StatusCode::kInvalidArgument, what);
}

// Windows and curtain walls: glass when edits.glass is on.
bool IsGlazing(std::string_view ifc_class) {
    return ifc_class.starts_with("IfcWindow") || ifc_class.starts_with("IfcCurtainWall");
}

// A vertical quad facing yaw: its normal (cos yaw, sin yaw, 0), counter-clockwise seen from there.
common::TriangleMesh MirrorMesh(const AddedMirror& m) {
    const Eigen::Vector3d side(-std::sin(m.yaw_deg * kDeg), std::cos(m.yaw_deg * kDeg), 0);
    const Eigen::Vector3d w = 0.5 * m.size.x() * side, h(0, 0, 0.5 * m.size.y());
    common::TriangleMesh out;
    const Eigen::Vector3d corners[4] = {m.center - w - h, m.center + w - h, m.center + w + h,
                                        m.center - w + h};
    for (const Eigen::Vector3d& c : corners) out.vertices.push_back(c.cast<float>());
    out.triangles = {{0, 1, 2}, {0, 2, 3}};
    return out;
}

void Append(common::TriangleMesh& to, std::vector<uint32_t>& ids, const common::TriangleMesh& m,
            uint32_t id) {
    const uint32_t base = uint32_t(to.vertices.size());
    to.vertices.insert(to.vertices.end(), m.vertices.begin(), m.vertices.end());
    for (const auto& t : m.triangles)
        to.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    ids.insert(ids.end(), m.triangles.size(), id);
}

// The vertices an element's triangles use (each element has its own, bim_model.hpp).
std::vector<uint32_t> ElementVertices(const bim::BimModel& m, const bim::BimElement& e) {
    std::set<uint32_t> v;
    for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
        v.insert(m.mesh.triangles[t].begin(), m.mesh.triangles[t].end());
    }
    return {v.begin(), v.end()};
}

void Transform(common::TriangleMesh& mesh, const std::vector<uint32_t>& vertices,
               const Eigen::Isometry3d& T) {
    for (const uint32_t i : vertices)
        mesh.vertices[i] = (T * mesh.vertices[i].cast<double>()).cast<float>();
}

Eigen::AlignedBox3d Bounds(const common::TriangleMesh& mesh,
                           const std::vector<uint32_t>& vertices) {
    Eigen::AlignedBox3d box;
    for (const uint32_t i : vertices) box.extend(mesh.vertices[i].cast<double>());
    return box;
}

// The ground: four quads around the footprint (xy box), facing up.
// A moved element's motion: turned about its centre c, then translated (edits.moved).
Eigen::Isometry3d Move(const MovedElement& mv, const Eigen::Vector3d& c) {
    return Eigen::Translation3d(c + mv.translation) *
           Eigen::AngleAxisd(mv.yaw_deg * kDeg, Eigen::Vector3d::UnitZ()) *
           Eigen::Translation3d(-c);
}

// An added mesh file, scaled, turned and placed where the scenario puts it.
common::TriangleMesh PlacedMesh(const AddedMesh& am) {
    common::TriangleMesh m = LoadMeshFile(am.file);
    const Eigen::Affine3d T = Eigen::Translation3d(am.position) *
                              Eigen::AngleAxisd(am.yaw_deg * kDeg, Eigen::Vector3d::UnitZ()) *
                              Eigen::Scaling(am.scale);
    for (auto& v : m.vertices) v = (T * v.cast<double>()).cast<float>();
    return m;
}

common::TriangleMesh Ground(const Eigen::AlignedBox3d& bounds, double z) {
    const Eigen::Vector2d lo = bounds.min().head<2>(), hi = bounds.max().head<2>();
    const double w = kGroundWidthM;
    common::TriangleMesh out;
    std::vector<uint32_t> unused;
    const Eigen::Vector2d rects[4][2] = {{{lo.x() - w, lo.y() - w}, {hi.x() + w, lo.y()}},
                                         {{lo.x() - w, hi.y()}, {hi.x() + w, hi.y() + w}},
                                         {{lo.x() - w, lo.y()}, {lo.x(), hi.y()}},
                                         {{hi.x(), lo.y()}, {hi.x() + w, hi.y()}}};
    for (const auto& r : rects) {
        const uint32_t b = uint32_t(out.vertices.size());
        const Eigen::Vector2d corners[4] = {r[0], {r[1].x(), r[0].y()}, r[1], {r[0].x(), r[1].y()}};
        for (const Eigen::Vector2d& c : corners) {
            out.vertices.emplace_back(float(c.x()), float(c.y()), float(z));
        }
        out.triangles.push_back({b, b + 1, b + 2});
        out.triangles.push_back({b, b + 2, b + 3});
    }
    return out;
}

// The horizontal direction a wall is thinnest in: the eigenvector of the smaller eigenvalue of
// its vertices' xy covariance.
Eigen::Vector2d WallNormal(const common::TriangleMesh& mesh,
                           const std::vector<uint32_t>& vertices) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const uint32_t i : vertices) mean += mesh.vertices[i].head<2>().cast<double>();
    mean /= double(vertices.size());
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const uint32_t i : vertices) {
        const Eigen::Vector2d d = mesh.vertices[i].head<2>().cast<double>() - mean;
        cov += d * d.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(cov);
    return solver.eigenvectors().col(0);
}

ElementChange ChangeOf(const bim::BimModel& m, size_t e, const std::string& change) {
    const bim::BimElement& el = m.elements[e];
    ElementChange c;
    c.change = change;
    c.global_id = el.global_id;
    c.ifc_class = el.ifc_class;
    c.name = el.name;
    c.storey = el.storey;
    return c;
}

double DistanceToPolyline(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& line) {
    double best = line.size() == 1 ? (line[0] - p).norm() : std::numeric_limits<double>::infinity();
    for (size_t i = 1; i < line.size(); ++i) {
        const Eigen::Vector2d a = line[i - 1], d = line[i] - a;
        const double f =
            d.squaredNorm() > 0 ? std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
        best = std::min(best, (a + f * d - p).norm());
    }
    return best;
}

size_t FindElement(const bim::BimModel& m, const std::string& global_id, const std::string& field) {
    for (size_t e = 0; e < m.elements.size(); ++e) {
        if (m.elements[e].global_id == global_id) return e;
    }
    Fail(field + " = '" + global_id + "': no element of the model has this GlobalId");
}

}  // namespace

std::map<std::string, common::TriangleMesh> NamedObjectMeshes(const EditsSpec& edits) {
    std::map<std::string, common::TriangleMesh> out;
    for (const AddedBox& b : edits.boxes) {
        out["box/" + b.name] = simulation::BoxMesh(b.center, b.size, b.yaw_deg * kDeg);
    }
    for (const AddedCylinder& c : edits.cylinders) {
        out["cylinder/" + c.name] = simulation::CylinderMesh(c.base, c.radius_m, c.height_m);
    }
    for (const AddedMesh& m : edits.meshes) out["mesh/" + m.name] = PlacedMesh(m);
    for (const AddedMirror& m : edits.mirrors) out["mirror/" + m.name] = MirrorMesh(m);
    return out;
}

std::vector<Obstacle> WalkObstacles(const bim::BimModel& model, const EditsSpec& edits) {
    std::vector<Obstacle> out;
    const auto name = [](const std::string& field, size_t k, const std::string& n) {
        return "edits." + field + "[" + std::to_string(k) + "]" + (n.empty() ? "" : " (" + n + ")");
    };
    for (size_t k = 0; k < edits.boxes.size(); ++k) {
        const AddedBox& b = edits.boxes[k];
        out.push_back(
            {name("boxes", k, b.name), simulation::BoxMesh(b.center, b.size, b.yaw_deg * kDeg)});
    }
    for (size_t k = 0; k < edits.cylinders.size(); ++k) {
        const AddedCylinder& c = edits.cylinders[k];
        out.push_back({name("cylinders", k, c.name),
                       simulation::CylinderMesh(c.base, c.radius_m, c.height_m)});
    }
    for (size_t k = 0; k < edits.meshes.size(); ++k) {
        const AddedMesh& am = edits.meshes[k];
        out.push_back({name("meshes", k, am.name), PlacedMesh(am)});
    }
    for (size_t k = 0; k < edits.moved.size(); ++k) {
        const size_t e = FindElement(model, edits.moved[k].global_id,
                                     "edits.moved[" + std::to_string(k) + "].global_id");
        const bim::BimElement& el = model.elements[e];
        const std::vector<uint32_t> v = ElementVertices(model, el);
        const Eigen::Isometry3d T = Move(edits.moved[k], Bounds(model.mesh, v).center());
        common::TriangleMesh m;
        m.vertices = model.mesh.vertices;  // only the element's are used, and moved
        Transform(m, v, T);
        m.triangles.assign(model.mesh.triangles.begin() + el.first_triangle,
                           model.mesh.triangles.begin() + el.first_triangle + el.triangle_count);
        out.push_back({name("moved", k, el.global_id), std::move(m)});
    }
    return out;
}

std::vector<uint8_t> RemovedElementMask(const bim::BimModel& model, const EditsSpec& edits) {
    std::vector<uint8_t> removed(model.elements.size(), 0);
    for (size_t k = 0; k < edits.removed.global_ids.size(); ++k) {
        const size_t e = FindElement(model, edits.removed.global_ids[k],
                                     "edits.removed.global_ids[" + std::to_string(k) + "]");
        removed[e] = 1;
    }
    for (size_t k = 0; k < edits.removed.classes.size(); ++k) {
        size_t matched = 0;
        for (size_t e = 0; e < model.elements.size(); ++e) {
            if (model.elements[e].ifc_class == edits.removed.classes[k]) removed[e] = 1, ++matched;
        }
        if (matched == 0) {
            Fail("edits.removed.classes[" + std::to_string(k) + "] = '" + edits.removed.classes[k] +
                 "': no element of the model has this class");
        }
    }
    return removed;
}

bim::BimModel PlanningModel(const bim::BimModel& model, const EditsSpec& edits, bool with_objects) {
    const std::vector<uint8_t> removed = RemovedElementMask(model, edits);
    const auto first = model.elements.data();
    bim::BimModel out = bim::SelectElements(model, [&](const bim::BimElement& e) {
        return !edits.removed.walk_through || !removed[size_t(&e - first)];
    });
    if (!edits.removed.walk_through || !with_objects) return out;
    // The added objects as elements of their own: objects (not structure), so that their
    // footprints below the grid's object height are occupied, as AddObstacle marks them.
    for (Obstacle& o : WalkObstacles(model, edits)) {
        bim::BimElement e;
        e.global_id = o.edit;
        e.ifc_class = "IfcBuildingElementProxy";
        e.name = o.edit;
        e.role = bim::ElementRole::kTransient;
        e.first_triangle = uint32_t(out.mesh.triangles.size());
        e.triangle_count = uint32_t(o.mesh.triangles.size());
        const auto base = uint32_t(out.mesh.vertices.size());
        out.mesh.vertices.insert(out.mesh.vertices.end(), o.mesh.vertices.begin(),
                                 o.mesh.vertices.end());
        for (const auto& t : o.mesh.triangles) {
            out.mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
            out.triangle_element.push_back(uint32_t(out.elements.size()));
        }
        out.elements.push_back(std::move(e));
    }
    return out;
}

namespace {

// The moved elements, moved in `model`; each said in w.changes.
void MoveElements(bim::BimModel& model, const EditsSpec& edits, World& w) {
    for (size_t k = 0; k < edits.moved.size(); ++k) {
        const MovedElement& mv = edits.moved[k];
        const size_t e =
            FindElement(model, mv.global_id, "edits.moved[" + std::to_string(k) + "].global_id");
        const std::vector<uint32_t> v = ElementVertices(model, model.elements[e]);
        Transform(model.mesh, v, Move(mv, Bounds(model.mesh, v).center()));
        ElementChange change = ChangeOf(model, e, "moved");
        change.translation = mv.translation;
        change.yaw_deg = mv.yaw_deg;
        w.changes.push_back(change);
    }
}

// The walls as built: those listed moved along their normal by their offset, the storey's others
// by a random one when as_built.wall_offset_sigma_m asks (drawn from rng, wall by wall).
void BuildWallsAsBuilt(bim::BimModel& model, int storey, const EditsSpec& edits,
                       const std::vector<uint8_t>& removed, std::mt19937_64& rng, World& w) {
    std::normal_distribution<double> normal(0.0, 1.0);
    for (size_t e = 0; e < model.elements.size(); ++e) {
        const bim::BimElement& el = model.elements[e];
        double offset = 0;
        bool listed = false;
        for (const WallOffset& wo : edits.as_built.walls) {
            if (wo.global_id == el.global_id) offset = wo.offset_m, listed = true;
        }
        const bool wall = el.ifc_class.starts_with("IfcWall") && el.storey == storey;
        if (!listed && wall && edits.as_built.wall_offset_sigma_m > 0) {
            offset = edits.as_built.wall_offset_sigma_m * normal(rng);
        }
        if (offset == 0 || removed[e]) continue;
        const std::vector<uint32_t> v = ElementVertices(model, el);
        const Eigen::Vector2d n = WallNormal(model.mesh, v);
        const Eigen::Vector3d t(offset * n.x(), offset * n.y(), 0);
        Transform(model.mesh, v, Eigen::Isometry3d(Eigen::Translation3d(t)));
        ElementChange change = ChangeOf(model, e, "as_built");
        change.translation = t;
        w.changes.push_back(change);
    }
    for (size_t k = 0; k < edits.as_built.walls.size(); ++k) {
        FindElement(model, edits.as_built.walls[k].global_id,
                    "edits.as_built.walls[" + std::to_string(k) + "].global_id");
    }
}

// The static scene: what is physically there, glazing as glass when asked, and the ground;
// the materials per triangle.
std::vector<simulation::Material> StaticScene(const bim::BimModel& model, const EditsSpec& edits,
                                              const std::vector<uint8_t>& removed, World& w) {
    std::vector<simulation::Material> materials;
    for (size_t e = 0; e < model.elements.size(); ++e) {
        const bim::BimElement& el = model.elements[e];
        const bool glass = edits.glass && IsGlazing(el.ifc_class);
        if (removed[e] || (bim::PassThrough(el.ifc_class) && !glass)) continue;
        for (uint32_t t = el.first_triangle; t < el.first_triangle + el.triangle_count; ++t) {
            w.mesh.triangles.push_back(model.mesh.triangles[t]);
            w.ids.push_back(uint32_t(e));
            materials.push_back(glass ? simulation::Material::kGlass
                                      : simulation::Material::kDiffuse);
        }
    }
    w.mesh.vertices = model.mesh.vertices;  // unused ones cost nothing to Embree
    const double ground_z = model.storeys.empty() ? 0.0 : model.storeys.front().elevation_m;
    Append(w.mesh, w.ids, Ground(model.Bounds(), ground_z - model.origin_m.z()), kGroundId);
    materials.resize(w.ids.size(), simulation::Material::kDiffuse);
    return materials;
}

// The scenario's boxes, cylinders, meshes and mirrors, into w.added.
void AddObjects(const EditsSpec& edits, World& w) {
    for (size_t k = 0; k < edits.boxes.size(); ++k) {
        const AddedBox& b = edits.boxes[k];
        w.added.push_back({b.name.empty() ? "box" + std::to_string(k) : b.name, "box",
                           simulation::BoxMesh(b.center, b.size, b.yaw_deg * kDeg)});
    }
    for (size_t k = 0; k < edits.cylinders.size(); ++k) {
        const AddedCylinder& c = edits.cylinders[k];
        w.added.push_back({c.name.empty() ? "cylinder" + std::to_string(k) : c.name, "cylinder",
                           simulation::CylinderMesh(c.base, c.radius_m, c.height_m)});
    }
    for (size_t k = 0; k < edits.meshes.size(); ++k) {
        const AddedMesh& am = edits.meshes[k];
        w.added.push_back(
            {am.name.empty() ? am.file.stem().string() : am.name, "mesh", PlacedMesh(am)});
    }
    for (size_t k = 0; k < edits.mirrors.size(); ++k) {
        const AddedMirror& m = edits.mirrors[k];
        w.added.push_back({m.name.empty() ? "mirror" + std::to_string(k) : m.name, "mirror",
                           MirrorMesh(m), simulation::Material::kMirror});
    }
}

// Clutter: boxes on free cells with room for them, clear of the walk and of every object added
// before them. Room is judged on circles in plan (each box's circumscribed circle, as for the
// walls): two solids cannot share space, and a box placed into another made the ground truth
// count two objects where a scanner sees one (stop 25: 8 of the 11 touching pairs in the
// changed-building benchmark's ten runs interpenetrated).
void AddClutter(const ClutterSpec& cl, const bim::OccupancyGrid& grid,
                const std::vector<Eigen::Vector2d>& walk, std::mt19937_64& rng, World& w) {
    std::vector<std::pair<Eigen::Vector2d, double>> taken;  // centre and radius in plan
    for (const AddedObject& a : w.added) {
        Eigen::AlignedBox2d box;
        for (const auto& v : a.mesh.vertices) box.extend(v.head<2>().cast<double>());
        double r = 0;
        for (const auto& v : a.mesh.vertices)
            r = std::max(r, (v.head<2>().cast<double>() - box.center()).norm());
        taken.emplace_back(box.center(), r);
    }
    if (cl.density_per_m2 <= 0) return;
    std::vector<size_t> free;
    for (size_t i = 0; i < grid.cells.size(); ++i) {
        if (grid.cells[i] == bim::Cell::kFree) free.push_back(i);
    }
    const double area = double(free.size()) * grid.resolution * grid.resolution;
    const size_t wanted = size_t(std::lround(cl.density_per_m2 * area));
    std::uniform_real_distribution<double> size(cl.min_size_m, cl.max_size_m), yaw(0, M_PI);
    size_t placed = 0;
    for (size_t attempt = 0; placed < wanted && attempt < 50 * wanted && !free.empty(); ++attempt) {
        const size_t i = free[std::uniform_int_distribution<size_t>(0, free.size() - 1)(rng)];
        const Eigen::Vector3d s(size(rng), size(rng), size(rng));
        const double half = 0.5 * std::hypot(s.x(), s.y());
        const Eigen::Vector2d c = grid.Center(int(i % grid.width), int(i / grid.width));
        if (grid.clearance[i] < half + kClutterGapM) continue;  // into a wall
        if (DistanceToPolyline(c, walk) < half + cl.keep_off_walk_m) continue;
        if (std::any_of(taken.begin(), taken.end(), [&](const auto& o) {
                return (c - o.first).norm() < half + o.second + kClutterGapM;
            })) {
            continue;
        }
        taken.emplace_back(c, half);
        w.added.push_back(
            {"clutter" + std::to_string(placed++), "clutter",
             simulation::BoxMesh({c.x(), c.y(), grid.floor_z + 0.5 * s.z()}, s, yaw(rng))});
    }
}

}  // namespace

World BuildWorld(const bim::BimModel& model_in, int storey, const EditsSpec& edits,
                 const bim::OccupancyGrid& grid, const std::vector<Eigen::Vector2d>& walk,
                 uint64_t seed) {
    bim::BimModel model = model_in;  // vertices are moved in place
    World w;
    const std::vector<uint8_t> removed = RemovedElementMask(model, edits);
    for (size_t e = 0; e < model.elements.size(); ++e) {
        if (removed[e]) w.changes.push_back(ChangeOf(model, e, "removed"));
    }
    MoveElements(model, edits, w);
    std::mt19937_64 rng(seed);  // the walls' offsets, then the clutter
    BuildWallsAsBuilt(model, storey, edits, removed, rng, w);
    std::vector<simulation::Material> materials = StaticScene(model, edits, removed, w);
    AddObjects(edits, w);
    AddClutter(edits.clutter, grid, walk, rng, w);
    for (size_t k = 0; k < w.added.size(); ++k) {
        Append(w.mesh, w.ids, w.added[k].mesh, kAddedIdBase + uint32_t(k));
        materials.resize(w.ids.size(), w.added[k].material);
    }
    if (edits.glass || !edits.mirrors.empty()) w.materials = std::move(materials);
    w.people = edits.people;
    w.doors = FindMovingDoors(model, edits.moving_doors, removed);
    w.people_floor_z = grid.floor_z;
    return w;
}

common::TriangleMesh PeopleMesh(const std::vector<PersonSpec>& people, double floor_z, double t,
                                std::vector<uint32_t>* ids) {
    common::TriangleMesh out;
    ids->clear();
    for (size_t k = 0; k < people.size(); ++k) {
        const PersonSpec& p = people[k];
        const double length = (p.to - p.from).norm();
        // To and fro: a triangle wave of the distance walked.
        const double s = std::fmod(p.speed_mps * t, 2 * length);
        const double along = s <= length ? s : 2 * length - s;
        const Eigen::Vector2d at = p.from + (p.to - p.from) * (along / length);
        Append(out, *ids,
               simulation::CylinderMesh(Eigen::Vector3d(at.x(), at.y(), floor_z), p.radius_m,
                                        p.height_m, 12),
               kPersonIdBase + uint32_t(k));
    }
    return out;
}

nlohmann::json WriteChanges(const World& world, const std::filesystem::path& dir) {
    using nlohmann::json;
    json added = json::array(), removed = json::array(), moved = json::array(),
         people = json::array();
    const std::filesystem::path folder = dir / "changes";
    if (!world.added.empty()) std::filesystem::create_directories(folder);
    for (size_t k = 0; k < world.added.size(); ++k) {
        const AddedObject& a = world.added[k];
        char stem[32];
        std::snprintf(stem, sizeof stem, "%03zu_", k);
        const std::string file = "changes/" + std::string(stem) + a.name + ".ply";
        io::WritePly(dir / file, io::ToPly(a.mesh));
        Eigen::AlignedBox3d box;
        for (const auto& v : a.mesh.vertices) box.extend(v.cast<double>());
        added.push_back({{"name", a.name},
                         {"kind", a.kind},
                         {"mesh", file},
                         {"box_min", {box.min().x(), box.min().y(), box.min().z()}},
                         {"box_max", {box.max().x(), box.max().y(), box.max().z()}}});
    }
    for (const ElementChange& c : world.changes) {
        json j = {{"global_id", c.global_id}, {"class", c.ifc_class}, {"name", c.name}};
        if (c.change == "removed") {
            removed.push_back(j);
            continue;
        }
        j["reason"] = c.change;
        j["translation"] = {c.translation.x(), c.translation.y(), c.translation.z()};
        j["yaw_deg"] = c.yaw_deg;
        moved.push_back(j);
    }
    json doors = json::array();
    for (const MovingDoor& d : world.doors) {
        doors.push_back({{"global_id", d.global_id},
                         {"hinge", {d.hinge.x(), d.hinge.y()}},
                         {"closed", {d.closed.x(), d.closed.y()}},
                         {"swing", {d.swing.x(), d.swing.y()}},
                         {"width_m", d.width_m},
                         {"height_m", d.height_m},
                         {"floor_z", d.floor_z},
                         {"period_s", d.period_s},
                         {"max_angle_deg", d.max_angle_deg},
                         {"phase", d.phase}});
    }
    for (const PersonSpec& p : world.people) {
        people.push_back({{"from", {p.from.x(), p.from.y()}},
                          {"to", {p.to.x(), p.to.y()}},
                          {"speed_mps", p.speed_mps},
                          {"radius_m", p.radius_m},
                          {"height_m", p.height_m},
                          {"floor_z", world.people_floor_z}});
    }
    return {{"frame", "bim"}, {"added", added},   {"removed", removed},
            {"moved", moved}, {"people", people}, {"moving_doors", doors}};
}

}  // namespace bimslam::simulate
