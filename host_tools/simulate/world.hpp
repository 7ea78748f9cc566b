// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The "real world" a capture is simulated in: the BIM as built, with the scenario's edits, and
// the ground truth of every edit (changes.json).
//
// What of the BIM is physically there: every element except doors (open, so the walk passes
// through them), windows, curtain walls and their panels (glass, which the LiDAR sees through;
// with edits.glass they are there as glass, simulation::Material::kGlass: they return near normal
// incidence and let the rest through), spaces and openings (not physical). Furniture and proxies
// are there, as are railings and stairs. Around the building's footprint lies a ground plane 40 m
// wide at the lowest storey's elevation (the outdoors of a walk that starts outside), with a hole
// under the building so that it does not double the ground floor's slab.
//
// Edits, in this order: removed elements (by GlobalId or class, any storey); moved elements
// (translated, and turned about the centre of their bounding box); as-built deviations (walls of
// the storey shifted along their horizontal normal, the direction of least horizontal extent of
// their vertices); added boxes, cylinders and meshes; random clutter (boxes on free floor cells of
// the storey, clear of the walk and of walls); mirrors (quads of Material::kMirror, reported as
// added objects of kind "mirror": a mirror hung on a wall is a real object the BIM lacks). People
// and moving doors are not in the static world: PeopleMesh and AppendDoorLeaves
// (moving_doors.hpp) build them per scan at their position at that time.
#pragma once

#include <map>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "algorithms/common/triangle_mesh.hpp"
#include "algorithms/simulation/scene.hpp"
#include "host_tools/bim/bim_model.hpp"
#include "host_tools/bim/occupancy_grid.hpp"
#include "host_tools/simulate/moving_doors.hpp"
#include "host_tools/simulate/scenario.hpp"

namespace bimslam::simulate {

struct AddedObject {
    std::string name;
    std::string kind;           // "box", "cylinder", "mesh", "clutter", "mirror"
    common::TriangleMesh mesh;  // BIM coordinates
    simulation::Material material = simulation::Material::kDiffuse;
};

struct ElementChange {
    std::string change;  // "removed", "moved", "as_built"
    std::string global_id;
    std::string ifc_class;
    std::string name;
    int storey = -1;
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();  // moved and as_built
    double yaw_deg = 0.0;                                   // moved
};

struct World {
    common::TriangleMesh mesh;  // the static scene
    std::vector<uint32_t> ids;  // per triangle: BIM element index, or kAddedIdBase + object
    // Per triangle; empty when all are diffuse (no glass, no mirrors).
    std::vector<simulation::Material> materials;
    std::vector<MovingDoor> doors;  // swung per scan in the overlay
    std::vector<AddedObject> added;
    std::vector<ElementChange> changes;
    std::vector<PersonSpec> people;
    double people_floor_z = 0.0;  // the storey's floor, where people walk
};
inline constexpr uint32_t kAddedIdBase = 1u << 30;
inline constexpr uint32_t kGroundId = kAddedIdBase - 1;
inline constexpr uint32_t kPersonIdBase = (1u << 31);
inline constexpr uint32_t kRigId = kPersonIdBase - 1;  // the platform's own body

// Throws common::Error naming the edit (its YAML path) when a GlobalId or class matches nothing,
// and what reading a mesh file throws (common::FileError naming the file).
World BuildWorld(const bim::BimModel& model, int storey, const EditsSpec& edits,
                 const bim::OccupancyGrid& grid, const std::vector<Eigen::Vector2d>& walk,
                 uint64_t seed);

// Per element of the model: 1 when the edits remove it (edits.removed: its GlobalIds and classes).
// Throws as BuildWorld does for a GlobalId or class that matches nothing.
std::vector<uint8_t> RemovedElementMask(const bim::BimModel& model, const EditsSpec& edits);

// The model the walk is planned on. Without edits.removed.walk_through: the model as it is (the
// scenario's objects are put on the walk's grid after its free space is found, AddObstacle). With
// it (a visit's default): the model without the removed elements (a demolished wall opens the
// way) and, `with_objects`, with the added objects and the moved elements at their new places
// (WalkObstacles) as elements of their own, so that they are on the grid before its free space is
// found: walls added outside the model close a room the walk can enter (through a door to the
// outside, or where a demolished facade stood). A moved element's old place stays in it.
bim::BimModel PlanningModel(const bim::BimModel& model, const EditsSpec& edits,
                            bool with_objects = true);

// What the scenario puts on the floor that the model does not have: the added boxes, cylinders
// and meshes, and the moved elements at their new places (model coordinates). The walk goes
// around them (walk.cpp). Throws as BuildWorld does for a GlobalId that matches nothing or a
// mesh file that cannot be read.
struct Obstacle {
    std::string edit;  // its YAML path and name, e.g. "edits.boxes[0] (crate)"
    common::TriangleMesh mesh;
};
std::vector<Obstacle> WalkObstacles(const bim::BimModel& model, const EditsSpec& edits);

// The scenario's boxes, cylinders, meshes and mirrors as BuildWorld places them, by "kind/name"
// (kind as in changes.json: box, cylinder, mesh, mirror). Throws what reading a mesh file throws.
std::map<std::string, common::TriangleMesh> NamedObjectMeshes(const EditsSpec& edits);

// The people at time t (seconds), as closed cylinders with triangle ids kPersonIdBase + person.
common::TriangleMesh PeopleMesh(const std::vector<PersonSpec>& people, double floor_z, double t,
                                std::vector<uint32_t>* ids);

// changes.json: the edits in BIM coordinates; each added object's mesh is written as
// `changes/<index>_<name>.ply` under `dir` and named in the JSON with its bounding box.
nlohmann::json WriteChanges(const World& world, const std::filesystem::path& dir);

// A PLY or OBJ mesh file (by extension). Throws common::FileError naming the file.
common::TriangleMesh LoadMeshFile(const std::filesystem::path& file);

}  // namespace bimslam::simulate
