// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A capture scenario: what `bimslam simulate` walks through, how, with which sensor, and how the
// "real world" differs from the BIM. Read from YAML (scenario_yaml.hpp; the keys are documented
// in host_tools/simulate/README.md, examples in host_tools/simulate/scenarios/); every field has
// a default, so an empty scenario is a Go1 coverage walk of the model's lowest storey (with 2 m
// or more to the next: bim::DefaultWalkStorey).
//
// Coordinates are the BIM's ("bim" frame, metres, z up); angles in the file are degrees (the
// fields carry _deg), everything else SI.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "drivers/go1/high_state.hpp"

namespace bimslam::simulate {

// Degrees to radians (the scenario's angles are in degrees).
inline constexpr double kDeg = M_PI / 180.0;

enum class Platform : uint8_t { kGo1, kHandheld, kVehicle };
enum class PathMode : uint8_t { kCoverage, kWaypoints };

struct Pose2d {
    Eigen::Vector2d xy = Eigen::Vector2d::Zero();
    double yaw_deg = 0.0;

    bool operator==(const Pose2d&) const = default;
};

struct PathSpec {
    PathMode mode = PathMode::kCoverage;
    std::vector<Eigen::Vector2d> waypoints;  // kWaypoints: visited in order (at least 1)
    // storey: all: the storey of each waypoint (by name); empty: every waypoint on the start
    // storey. A* over the building's 3D graph joins them (building_walk.hpp).
    std::vector<std::string> waypoint_storeys;
    // Where the walk starts; may be outside the building (it then walks in through a door).
    // Without it: the coverage walk's first viewpoint, or the first waypoint, facing along the
    // walk.
    std::optional<Pose2d> start;

    bool operator==(const PathSpec&) const = default;
};

struct SpeedSpec {
    double speed_mps = 0.5;            // cruise speed (Go1 trot ~0.5, a person ~1.0)
    double max_accel_mps2 = 0.5;       // start, stop and braking before turns
    double max_yaw_rate_deg_s = 57.3;  // turns are slowed to this (1 rad/s)
    double max_lateral_accel_mps2 = 0.5;
    // The capture starts where the walk first reaches its cruise speed, not standing still: a
    // recording started in motion (simulation::PathTiming::start_at_speed).
    bool start_at_speed = false;

    bool operator==(const SpeedSpec&) const = default;
};

// The sensor: a built-in one (drivers/ouster BuiltinOuster) or a metadata file.
struct SensorSpec {
    std::filesystem::path metadata;      // empty: the built-in `model`
    std::string model = "OS1-32";        // built-in: OS0, OS1 or OS2 with 16, 32, 64 or 128 beams
    std::string lidar_mode = "1024x10";  // 512x10, 1024x10, 2048x10, 1024x20
    std::string udp_profile = "RNG19";   // LEGACY, RNG19, RNG15, DUAL
    // T_base_sensor: the sensor on the platform's base (the Go1 trunk centre, or the handheld
    // rig's handle). Default: on the Go1's back, 0.28 m above the trunk centre.
    Eigen::Vector3d mount_xyz{0.05, 0.0, 0.28};
    Eigen::Vector3d mount_rpy_deg{0.0, 0.0, 0.0};
    // The platform's own body in view (rig_body.hpp): the Go1's trunk and legs, the person
    // carrying the sensor, the car's roof and body. Off by default, as most captures so far.
    bool body_in_view = false;
    // A step of the sensor's clock (a restart, or its time source stepping): from clock_jump_at_s
    // of the walk on, the packets' timestamps (lidar columns and IMU) are clock_jump_s later; the
    // capture's time stamps and the truth keep the true time. 0: none. The rig's odometry starts
    // again there, in a new frame (algorithms/pipeline/scan_pipeline.hpp, clock_jump_forward_s).
    double clock_jump_at_s = 0;
    double clock_jump_s = 0;

    bool operator==(const SensorSpec&) const = default;
};

struct NetworkSpec {
    bool fragment = true;      // cut datagrams at MTU 1500, as a real link does
    double packet_loss = 0.0;  // probability of losing each UDP datagram, [0, 1)
    // How go1_highstate.pcap stores each HighState's CRC: scrambled by the SDK's encryptCRC, as
    // the robot's sport controller sends it (drivers/go1/README.md), or plain.
    go1::CrcForm go1_highstate_crc = go1::CrcForm::kScrambled;

    bool operator==(const NetworkSpec&) const = default;
};

struct LidarNoiseSpec {
    double range_sigma_m = 0.01;
    double dropout = 0.001;  // base dropout probability (simulation::NoiseModel::dropout_base)
    double max_range_m = 100.0;
    // Glass (edits.glass) returns from the pane with probability p0 cos(a)^k at incidence a
    // (simulation::NoiseModel::glass_return_probability and _exponent, where the defaults are
    // justified).
    double glass_return_probability = 0.5;
    double glass_return_exponent = 30.0;

    bool operator==(const LidarNoiseSpec&) const = default;
};

struct ImuNoiseSpec {
    double accel_sigma_mps2 = 0.02;       // white noise per sample
    double gyro_sigma_deg_s = 0.05;       // white noise per sample
    double accel_bias_sigma_mps2 = 0.05;  // constant bias per axis, drawn once
    double gyro_bias_sigma_deg_s = 0.2;   // constant bias per axis, drawn once

    bool operator==(const ImuNoiseSpec&) const = default;
};

// Leg odometry errors of the Go1 (what its HighState velocity and position report).
struct OdometryNoiseSpec {
    double scale_error = 0.03;           // velocity reads (1 + scale_error) times the truth
    double velocity_sigma_mps = 0.02;    // white noise on vx, vy per sample
    double yaw_drift_deg_per_min = 2.0;  // yaw-rate bias
    double slips_per_min = 1.0;          // foot slips: Poisson events
    double slip_duration_s = 0.3;        // during a slip the velocity reads slip_factor of truth
    double slip_factor = 0.3;

    bool operator==(const OdometryNoiseSpec&) const = default;
};

struct NoiseSpec {
    LidarNoiseSpec lidar;
    ImuNoiseSpec imu;
    OdometryNoiseSpec odometry;

    bool operator==(const NoiseSpec&) const = default;
};

// Scene edits: the "real world" that the BIM does not show.
struct AddedBox {
    std::string name;
    Eigen::Vector3d center = Eigen::Vector3d::Zero();  // of the box
    Eigen::Vector3d size = Eigen::Vector3d::Ones();
    double yaw_deg = 0.0;

    bool operator==(const AddedBox&) const = default;
};
struct AddedCylinder {
    std::string name;
    Eigen::Vector3d base = Eigen::Vector3d::Zero();  // centre of the bottom face
    double radius_m = 0.25;
    double height_m = 1.0;

    bool operator==(const AddedCylinder&) const = default;
};
struct AddedMesh {
    std::string name;
    std::filesystem::path file;  // PLY or OBJ, metres; relative to the scenario file
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    double yaw_deg = 0.0;
    double scale = 1.0;

    bool operator==(const AddedMesh&) const = default;
};
// Random boxes on the storey's free floor, away from the walk, 5 cm or more from the walls and
// from every other added object (world.cpp).
struct ClutterSpec {
    double density_per_m2 = 0.0;  // objects per square metre of free floor; 0: none
    double min_size_m = 0.2;
    double max_size_m = 0.8;
    double keep_off_walk_m = 0.6;  // no object closer than this to the walk

    bool operator==(const ClutterSpec&) const = default;
};
struct RemovedElements {
    std::vector<std::string> global_ids;
    std::vector<std::string> classes;  // e.g. IfcDoor: every element of the class on the storey
    // The walk is planned without them (PlanningModel, world.hpp): a demolished wall opens the
    // way. Off by default, so that the captures made before it stay the same; on by default in a
    // visit's edits (VisitSpec).
    bool walk_through = false;

    bool operator==(const RemovedElements&) const = default;
};
struct MovedElement {
    std::string global_id;
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();
    double yaw_deg = 0.0;  // about the element's centre

    bool operator==(const MovedElement&) const = default;
};
struct WallOffset {
    std::string global_id;
    double offset_m = 0.0;  // along the wall's horizontal normal

    bool operator==(const WallOffset&) const = default;
};
struct AsBuiltSpec {
    double wall_offset_sigma_m = 0.0;  // every wall of the storey shifted by N(0, sigma^2)
    std::vector<WallOffset> walls;     // and these by exactly this much

    bool operator==(const AsBuiltSpec&) const = default;
};
struct PersonSpec {
    Eigen::Vector2d from = Eigen::Vector2d::Zero();  // walks from -> to -> from ... on the floor
    Eigen::Vector2d to = Eigen::Vector2d::Zero();
    double speed_mps = 1.2;
    double radius_m = 0.25;
    double height_m = 1.75;

    bool operator==(const PersonSpec&) const = default;
};

// A flat mirror: a vertical rectangle facing `yaw_deg` (its normal (cos yaw, sin yaw, 0)).
struct AddedMirror {
    std::string name;
    Eigen::Vector3d center = Eigen::Vector3d::Zero();  // of the reflecting face
    Eigen::Vector2d size{1.0, 1.5};                    // width, height
    double yaw_deg = 0.0;

    bool operator==(const AddedMirror&) const = default;
};
// Doors that swing: a leaf of the door's width and height turning about its hinge, the angle
// max_angle_deg (1 - cos(2 pi (t / period_s + phase))) / 2 from closed, a phase per door.
// Without classes or global_ids: none (doors stay open and absent, as the BIM's doors are).
struct MovingDoorsSpec {
    std::vector<std::string> global_ids;
    std::vector<std::string> classes;  // e.g. IfcDoor: every element of the class
    double period_s = 8.0;
    double max_angle_deg = 90.0;

    bool operator==(const MovingDoorsSpec&) const = default;
};

struct EditsSpec {
    std::vector<AddedBox> boxes;
    std::vector<AddedCylinder> cylinders;
    std::vector<AddedMesh> meshes;
    ClutterSpec clutter;
    RemovedElements removed;
    std::vector<MovedElement> moved;
    AsBuiltSpec as_built;
    std::vector<PersonSpec> people;
    // Windows and curtain walls as glass (simulation::Material::kGlass) instead of left out.
    bool glass = false;
    std::vector<AddedMirror> mirrors;
    MovingDoorsSpec moving_doors;

    bool operator==(const EditsSpec&) const = default;
};

// One visit of the building (issue 33): a capture of its own, on its own date, with its own
// edits. The keys it does not give are the top-level scenario's (VisitScenario).
struct VisitSpec {
    std::string label;  // its folder under the output: a plain file name, unique
    std::string date;   // ISO 8601 UTC, required
    std::optional<Platform> platform;
    std::optional<uint64_t> seed;
    std::optional<PathSpec> path;  // replaces the top level's path as a whole
    std::optional<double> duration_s;
    std::optional<std::string> storey;
    // The visit's whole edit set relative to the MODEL (not to the previous visit); replaces the
    // top level's edits as a whole. Without it: the top level's.
    std::optional<EditsSpec> edits;

    bool operator==(const VisitSpec&) const = default;
};

// storey: all walks every storey the stairs reach (building_walk.hpp).
inline constexpr const char* kAllStoreys = "all";

struct Scenario {
    std::filesystem::path model;  // IFC file; relative to the scenario file (--model overrides)
    // empty: bim::DefaultWalkStorey; "all" (kAllStoreys): every storey the stairs reach
    std::string storey;
    Platform platform = Platform::kGo1;
    PathSpec path;
    SpeedSpec speed;
    double duration_s = 0.0;  // 0: the whole walk once; more: the walk repeats until then
    SensorSpec sensor;
    NetworkSpec network;
    NoiseSpec noise;
    uint64_t seed = 1;
    // When the walk starts, ISO 8601 (common::ParseUtcTime, e.g. 2026-03-02T09:30:00Z): the pcap's
    // and CAN log's host clock at t = 0. Empty: 2023-11-14T22:13:20Z (kDefaultStartNs).
    std::string date;
    EditsSpec edits;
    // Visits over time (issue 33, item 7): with them, `bimslam simulate` writes one capture per
    // visit (visits.hpp); the top-level keys are what the visits do not set.
    std::vector<VisitSpec> visits;

    // Throws common::Error (kInvalidArgument) naming the field (as in the YAML, e.g.
    // "speed.speed_mps") and the value.
    void Validate() const;

    // Field by field (exact), e.g. for checking that a scenario survives YAML.
    bool operator==(const Scenario&) const = default;
};

// Visit i of `scenario` as a scenario of its own (no visits): the top level's keys with the
// visit's in their place. A visit with another platform than the top level's also takes that
// platform's speed and sensor mount (DefaultScenario).
Scenario VisitScenario(const Scenario& scenario, size_t i);
// The index of the visit labelled `label`; throws common::Error naming the labels there are.
size_t FindVisit(const Scenario& scenario, const std::string& label);

// The defaults for a platform: a Go1 trots at 0.5 m/s with the sensor on its back; a person
// walks at 1.0 m/s holding the sensor 0.1 m above the handheld base, which is already at chest
// height (simulation::GaitConfig::Handheld); a vehicle drives waypoints outdoors at 3 m/s with the
// sensor 0.2 m above its roof (simulation::GaitConfig::Vehicle). A vehicle has no default path:
// it needs path.mode waypoints, outside the building (scenarios/vehicle_outdoor.yaml).
Scenario DefaultScenario(Platform platform = Platform::kGo1);

// "go1", "handheld", "vehicle"; "coverage", "waypoints": the YAML spellings.
std::string_view ToString(Platform platform);
std::string_view ToString(PathMode mode);
// The inverses; nullopt for any other text.
std::optional<Platform> PlatformFromString(std::string_view text);
std::optional<PathMode> PathModeFromString(std::string_view text);

// "path[i]": how error messages name the i-th item of a list (Validate() and the YAML reader).
std::string ItemPath(const std::string& path, size_t i);

}  // namespace bimslam::simulate
