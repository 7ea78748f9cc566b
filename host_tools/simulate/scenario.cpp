// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/simulate/scenario.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <string>

#include "algorithms/common/status.hpp"
#include "algorithms/common/utc_time.hpp"

namespace bimslam::simulate {
namespace {

using common::StatusCode;

constexpr std::array<std::string_view, 4> kLidarModes = {"512x10", "1024x10", "2048x10", "1024x20"};
constexpr std::array<std::string_view, 4> kUdpProfiles = {"LEGACY", "RNG19", "RNG15", "DUAL"};
constexpr std::array<std::string_view, 12> kSensorModels = {
    "OS0-16", "OS0-32",  "OS0-64", "OS0-128", "OS1-16", "OS1-32",
    "OS1-64", "OS1-128", "OS2-16", "OS2-32",  "OS2-64", "OS2-128"};

// Shortest text that reads back to the same double, so a message shows what the file said.
std::string Num(double x) {
    std::array<char, 32> buf{};
    const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), x);
    return std::string(buf.data(), r.ptr);
}

template <int N>
std::string Vec(const Eigen::Matrix<double, N, 1>& v) {
    std::string s = "[";
    for (int i = 0; i < N; ++i) s += (i ? ", " : "") + Num(v[i]);
    return s + "]";
}

// Messages read "<yaml key path> = <value>: <rule>".
void Require(bool ok, const std::string& field, const std::string& value, const char* rule) {
    if (!ok) throw common::Error(StatusCode::kInvalidArgument, field + " = " + value + ": " + rule);
}

bool Finite(double x) { return std::isfinite(x); }

void RequireFinite(const std::string& field, double x) {
    Require(Finite(x), field, Num(x), "must be finite");
}
template <int N>
void RequireFinite(const std::string& field, const Eigen::Matrix<double, N, 1>& v) {
    Require(v.allFinite(), field, Vec(v), "must be finite");
}
void RequireNonNegative(const std::string& field, double x) {
    Require(Finite(x) && x >= 0, field, Num(x), "must be >= 0");
}
void RequirePositive(const std::string& field, double x) {
    Require(Finite(x) && x > 0, field, Num(x), "must be > 0");
}
// Bounded above as well: a typo such as 50 for 0.5 m/s would otherwise run silently.
void RequireInRange(const std::string& field, double x, double lo_excl, double hi_incl,
                    const char* rule) {
    Require(Finite(x) && x > lo_excl && x <= hi_incl, field, Num(x), rule);
}
void RequireProbability(const std::string& field, double x) {
    Require(Finite(x) && x >= 0 && x < 1, field, Num(x), "must be in [0, 1)");
}
void RequireNonEmpty(const std::string& field, const std::string& s) {
    Require(!s.empty(), field, "''", "must not be empty");
}
void RequireIfcClass(const std::string& field, const std::string& s) {
    Require(s.size() > 3 && s.compare(0, 3, "Ifc") == 0, field, "'" + s + "'",
            "must be an IFC class name such as IfcDoor");
}

template <size_t N>
void RequireOneOf(const std::string& field, const std::string& value,
                  const std::array<std::string_view, N>& allowed) {
    bool ok = false;
    std::string list;
    for (const auto a : allowed) {
        ok = ok || value == a;
        list += (list.empty() ? "" : ", ") + std::string(a);
    }
    if (!ok) {
        throw common::Error(StatusCode::kInvalidArgument,
                            field + " = '" + value + "': must be one of " + list);
    }
}

void ValidateSpeed(const SpeedSpec& s) {
    RequireInRange("speed.speed_mps", s.speed_mps, 0, 5, "must be > 0 and <= 5");
    RequireInRange("speed.max_accel_mps2", s.max_accel_mps2, 0, 10, "must be > 0 and <= 10");
    RequireInRange("speed.max_yaw_rate_deg_s", s.max_yaw_rate_deg_s, 0, 720,
                   "must be > 0 and <= 720");
    RequireInRange("speed.max_lateral_accel_mps2", s.max_lateral_accel_mps2, 0, 10,
                   "must be > 0 and <= 10");
}

void ValidatePath(const PathSpec& p) {
    Require(p.mode == PathMode::kCoverage || p.mode == PathMode::kWaypoints, "path.mode",
            std::to_string(static_cast<int>(p.mode)), "must be coverage or waypoints");
    if (p.mode == PathMode::kWaypoints) {
        Require(!p.waypoints.empty(), "path.waypoints", "[]",
                "mode waypoints needs at least 1 waypoint");
    } else {
        Require(p.waypoints.empty(), "path.waypoints",
                std::to_string(p.waypoints.size()) + " points",
                "must be empty with mode coverage (the walk is planned)");
    }
    for (size_t i = 0; i < p.waypoints.size(); ++i) {
        RequireFinite(ItemPath("path.waypoints", i), p.waypoints[i]);
    }
    Require(
        p.waypoint_storeys.empty() || p.waypoint_storeys.size() == p.waypoints.size(),
        "path.waypoint_storeys", std::to_string(p.waypoint_storeys.size()) + " names",
        ("must name one storey per waypoint (" + std::to_string(p.waypoints.size()) + ")").c_str());
    if (p.start) {
        RequireFinite("path.start.xy", p.start->xy);
        RequireFinite("path.start.yaw_deg", p.start->yaw_deg);
    }
}

void ValidateSensor(const SensorSpec& s) {
    RequireOneOf("sensor.model", s.model, kSensorModels);
    RequireOneOf("sensor.lidar_mode", s.lidar_mode, kLidarModes);
    RequireOneOf("sensor.udp_profile", s.udp_profile, kUdpProfiles);
    // Within a few metres of the base: a rig, not a crane.
    Require(s.mount_xyz.allFinite() && s.mount_xyz.cwiseAbs().maxCoeff() <= 3.0, "sensor.mount_xyz",
            Vec(s.mount_xyz), "must be finite, each within [-3, 3] m");
    Require(s.mount_rpy_deg.allFinite() && s.mount_rpy_deg.cwiseAbs().maxCoeff() <= 180.0,
            "sensor.mount_rpy_deg", Vec(s.mount_rpy_deg),
            "must be finite, each within [-180, 180]");
    Require(std::isfinite(s.clock_jump_s) && std::abs(s.clock_jump_s) <= 3600, "sensor.clock_jump_s",
            std::to_string(s.clock_jump_s), "must be within [-3600, 3600] s");
    Require(std::isfinite(s.clock_jump_at_s) && (s.clock_jump_s == 0 || s.clock_jump_at_s > 0),
            "sensor.clock_jump_at_s", std::to_string(s.clock_jump_at_s),
            "must be after the start of the walk (> 0 s) when sensor.clock_jump_s is set");
}

void ValidateNoise(const NoiseSpec& n) {
    Require(
        Finite(n.lidar.range_sigma_m) && n.lidar.range_sigma_m >= 0 && n.lidar.range_sigma_m <= 1,
        "noise.lidar.range_sigma_m", Num(n.lidar.range_sigma_m), "must be in [0, 1]");
    RequireProbability("noise.lidar.dropout", n.lidar.dropout);
    RequireInRange("noise.lidar.max_range_m", n.lidar.max_range_m, 0, 1000,
                   "must be > 0 and <= 1000");
    Require(Finite(n.lidar.glass_return_probability) && n.lidar.glass_return_probability >= 0 &&
                n.lidar.glass_return_probability <= 1,
            "noise.lidar.glass_return_probability", Num(n.lidar.glass_return_probability),
            "must be in [0, 1]");
    Require(Finite(n.lidar.glass_return_exponent) && n.lidar.glass_return_exponent >= 0 &&
                n.lidar.glass_return_exponent <= 1000,
            "noise.lidar.glass_return_exponent", Num(n.lidar.glass_return_exponent),
            "must be in [0, 1000]");
    RequireNonNegative("noise.imu.accel_sigma_mps2", n.imu.accel_sigma_mps2);
    RequireNonNegative("noise.imu.gyro_sigma_deg_s", n.imu.gyro_sigma_deg_s);
    RequireNonNegative("noise.imu.accel_bias_sigma_mps2", n.imu.accel_bias_sigma_mps2);
    RequireNonNegative("noise.imu.gyro_bias_sigma_deg_s", n.imu.gyro_bias_sigma_deg_s);
    const OdometryNoiseSpec& o = n.odometry;
    Require(Finite(o.scale_error) && std::abs(o.scale_error) < 1, "noise.odometry.scale_error",
            Num(o.scale_error), "must be in (-1, 1)");
    RequireNonNegative("noise.odometry.velocity_sigma_mps", o.velocity_sigma_mps);
    RequireFinite("noise.odometry.yaw_drift_deg_per_min", o.yaw_drift_deg_per_min);
    RequireNonNegative("noise.odometry.slips_per_min", o.slips_per_min);
    RequireNonNegative("noise.odometry.slip_duration_s", o.slip_duration_s);
    Require(Finite(o.slip_factor) && o.slip_factor >= 0 && o.slip_factor <= 1,
            "noise.odometry.slip_factor", Num(o.slip_factor), "must be in [0, 1]");
}

void ValidateEdits(const EditsSpec& e) {
    for (size_t i = 0; i < e.boxes.size(); ++i) {
        const std::string p = ItemPath("edits.boxes", i);
        const AddedBox& b = e.boxes[i];
        RequireFinite(p + ".center", b.center);
        Require(b.size.allFinite() && (b.size.array() > 0).all(), p + ".size", Vec(b.size),
                "must be finite and > 0 in each axis");
        RequireFinite(p + ".yaw_deg", b.yaw_deg);
    }
    for (size_t i = 0; i < e.cylinders.size(); ++i) {
        const std::string p = ItemPath("edits.cylinders", i);
        RequireFinite(p + ".base", e.cylinders[i].base);
        RequirePositive(p + ".radius_m", e.cylinders[i].radius_m);
        RequirePositive(p + ".height_m", e.cylinders[i].height_m);
    }
    for (size_t i = 0; i < e.meshes.size(); ++i) {
        const std::string p = ItemPath("edits.meshes", i);
        const AddedMesh& m = e.meshes[i];
        RequireNonEmpty(p + ".file", m.file.string());
        RequireFinite(p + ".position", m.position);
        RequireFinite(p + ".yaw_deg", m.yaw_deg);
        RequirePositive(p + ".scale", m.scale);
    }
    const ClutterSpec& c = e.clutter;
    Require(Finite(c.density_per_m2) && c.density_per_m2 >= 0 && c.density_per_m2 <= 5,
            "edits.clutter.density_per_m2", Num(c.density_per_m2), "must be in [0, 5]");
    RequirePositive("edits.clutter.min_size_m", c.min_size_m);
    RequirePositive("edits.clutter.max_size_m", c.max_size_m);
    Require(c.min_size_m <= c.max_size_m, "edits.clutter.max_size_m", Num(c.max_size_m),
            "must be >= edits.clutter.min_size_m");
    RequireNonNegative("edits.clutter.keep_off_walk_m", c.keep_off_walk_m);
    for (size_t i = 0; i < e.removed.global_ids.size(); ++i) {
        RequireNonEmpty(ItemPath("edits.removed.global_ids", i), e.removed.global_ids[i]);
    }
    for (size_t i = 0; i < e.removed.classes.size(); ++i) {
        RequireIfcClass(ItemPath("edits.removed.classes", i), e.removed.classes[i]);
    }
    for (size_t i = 0; i < e.moved.size(); ++i) {
        const std::string p = ItemPath("edits.moved", i);
        RequireNonEmpty(p + ".global_id", e.moved[i].global_id);
        RequireFinite(p + ".translation", e.moved[i].translation);
        RequireFinite(p + ".yaw_deg", e.moved[i].yaw_deg);
    }
    Require(Finite(e.as_built.wall_offset_sigma_m) && e.as_built.wall_offset_sigma_m >= 0 &&
                e.as_built.wall_offset_sigma_m <= 1,
            "edits.as_built.wall_offset_sigma_m", Num(e.as_built.wall_offset_sigma_m),
            "must be in [0, 1]");
    for (size_t i = 0; i < e.as_built.walls.size(); ++i) {
        const std::string p = ItemPath("edits.as_built.walls", i);
        RequireNonEmpty(p + ".global_id", e.as_built.walls[i].global_id);
        RequireFinite(p + ".offset_m", e.as_built.walls[i].offset_m);
    }
    for (size_t i = 0; i < e.people.size(); ++i) {
        const std::string p = ItemPath("edits.people", i);
        const PersonSpec& q = e.people[i];
        RequireFinite(p + ".from", q.from);
        RequireFinite(p + ".to", q.to);
        Require(q.from != q.to, p + ".to", Vec(q.to), "must differ from .from");
        RequireInRange(p + ".speed_mps", q.speed_mps, 0, 5, "must be > 0 and <= 5");
        RequireInRange(p + ".radius_m", q.radius_m, 0, 2, "must be > 0 and <= 2");
        RequireInRange(p + ".height_m", q.height_m, 0, 3, "must be > 0 and <= 3");
    }
    for (size_t i = 0; i < e.mirrors.size(); ++i) {
        const std::string p = ItemPath("edits.mirrors", i);
        const AddedMirror& m = e.mirrors[i];
        RequireFinite(p + ".center", m.center);
        Require(m.size.allFinite() && (m.size.array() > 0).all() && (m.size.array() <= 20).all(),
                p + ".size", Vec(m.size), "must be > 0 and <= 20 m in each axis");
        RequireFinite(p + ".yaw_deg", m.yaw_deg);
    }
    const MovingDoorsSpec& d = e.moving_doors;
    for (size_t i = 0; i < d.global_ids.size(); ++i) {
        RequireNonEmpty(ItemPath("edits.moving_doors.global_ids", i), d.global_ids[i]);
    }
    for (size_t i = 0; i < d.classes.size(); ++i) {
        RequireIfcClass(ItemPath("edits.moving_doors.classes", i), d.classes[i]);
    }
    RequireInRange("edits.moving_doors.period_s", d.period_s, 0, 3600, "must be > 0 and <= 3600");
    Require(Finite(d.max_angle_deg) && d.max_angle_deg >= 0 && d.max_angle_deg <= 180,
            "edits.moving_doors.max_angle_deg", Num(d.max_angle_deg), "must be in [0, 180]");
}

// A folder name that means the same on every system: letters, digits, '.', '_', '-', not
// starting with '.' (so never "." or "..").
bool PlainFileName(const std::string& s) {
    if (s.empty() || s[0] == '.') return false;
    for (const char c : s) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                        (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
        if (!ok) return false;
    }
    return true;
}

// Objects are matched across visits by name (visits.hpp): in each visit, every box, cylinder,
// mesh and mirror needs a name of its own. `at` is where the edits stand ("visits[1]." or "").
void RequireUniqueNames(const EditsSpec& e, const std::string& at) {
    std::vector<std::string> seen;
    auto check = [&](const std::string& field, size_t i, const std::string& name) {
        const std::string p = at + ItemPath("edits." + field, i) + ".name";
        Require(!name.empty(), p, "''", "a visit's objects are matched across visits by name");
        Require(std::find(seen.begin(), seen.end(), name) == seen.end(), p, "'" + name + "'",
                "another object of the visit has this name (objects are matched by name)");
        seen.push_back(name);
    };
    for (size_t i = 0; i < e.boxes.size(); ++i) check("boxes", i, e.boxes[i].name);
    for (size_t i = 0; i < e.cylinders.size(); ++i) check("cylinders", i, e.cylinders[i].name);
    for (size_t i = 0; i < e.meshes.size(); ++i) check("meshes", i, e.meshes[i].name);
    for (size_t i = 0; i < e.mirrors.size(); ++i) check("mirrors", i, e.mirrors[i].name);
}

void ValidateVisits(const Scenario& s) {
    for (size_t i = 0; i < s.visits.size(); ++i) {
        const VisitSpec& v = s.visits[i];
        const std::string p = ItemPath("visits", i);
        Require(PlainFileName(v.label), p + ".label", "'" + v.label + "'",
                "must be a folder name: letters, digits, '.', '_' or '-', not starting with '.'");
        for (size_t j = 0; j < i; ++j) {
            Require(
                s.visits[j].label != v.label, p + ".label", "'" + v.label + "'",
                ("the label of " + ItemPath("visits", j) + " too: labels name folders").c_str());
        }
        Require(!v.date.empty(), p + ".date", "''",
                "every visit needs its date (ISO 8601 UTC, e.g. 2026-03-02T09:30:00Z)");
        try {
            VisitScenario(s, i).Validate();
        } catch (const common::Error& e) {
            throw common::Error(e.code(), p + "." + e.what());
        }
        RequireUniqueNames(v.edits ? *v.edits : s.edits, v.edits ? p + "." : "");
    }
}

}  // namespace

void Scenario::Validate() const {
    Require(platform == Platform::kGo1 || platform == Platform::kHandheld ||
                platform == Platform::kVehicle,
            "platform", std::to_string(static_cast<int>(platform)),
            "must be go1, handheld or vehicle");
    // A vehicle drives outdoors, around the building: no coverage walk of its rooms.
    Require(platform != Platform::kVehicle ||
                (path.mode == PathMode::kWaypoints && !path.waypoints.empty()),
            "path",
            std::string(ToString(path.mode)) + " with " + std::to_string(path.waypoints.size()) +
                " waypoints",
            "a vehicle drives waypoints outside the building: give path.mode waypoints and "
            "path.waypoints (host_tools/simulate/scenarios/vehicle_outdoor.yaml)");
    ValidatePath(path);
    ValidateSpeed(speed);
    RequireNonNegative("duration_s", duration_s);
    ValidateSensor(sensor);
    RequireProbability("network.packet_loss", network.packet_loss);
    ValidateNoise(noise);
    ValidateEdits(edits);
    if (!date.empty()) {
        try {
            (void)common::ParseUtcTime(date);
        } catch (const common::Error& e) {
            throw common::Error(common::StatusCode::kInvalidArgument,
                                "date = " + std::string(e.what()));
        }
    }
    ValidateVisits(*this);
}

Scenario VisitScenario(const Scenario& s, size_t i) {
    const VisitSpec& v = s.visits.at(i);
    Scenario out = s;
    out.visits.clear();
    if (v.platform && *v.platform != s.platform) {
        const Scenario defaults = DefaultScenario(*v.platform);
        out.platform = *v.platform;
        out.speed = defaults.speed;
        out.sensor.mount_xyz = defaults.sensor.mount_xyz;
        out.sensor.mount_rpy_deg = defaults.sensor.mount_rpy_deg;
    }
    if (v.seed) out.seed = *v.seed;
    if (v.path) out.path = *v.path;
    if (v.duration_s) out.duration_s = *v.duration_s;
    if (v.storey) out.storey = *v.storey;
    if (v.edits) out.edits = *v.edits;
    out.date = v.date;
    return out;
}

size_t FindVisit(const Scenario& s, const std::string& label) {
    std::string labels;
    for (size_t i = 0; i < s.visits.size(); ++i) {
        if (s.visits[i].label == label) return i;
        labels += (labels.empty() ? "" : ", ") + s.visits[i].label;
    }
    throw common::Error(StatusCode::kInvalidArgument,
                        "no visit labelled '" + label + "'" +
                            (labels.empty() ? " (the scenario has no visits)"
                                            : " (the scenario's: " + labels + ")"));
}

Scenario DefaultScenario(Platform platform) {
    Scenario s;
    s.platform = platform;
    if (platform == Platform::kHandheld) {
        s.speed.speed_mps = 1.0;
        s.speed.max_yaw_rate_deg_s = 90.0;
        // The handheld base is already at chest height (GaitConfig::Handheld): the sensor sits
        // just above the hand.
        s.sensor.mount_xyz = Eigen::Vector3d(0.0, 0.0, 0.1);
    } else if (platform == Platform::kVehicle) {
        // A car at town speed: gentle starts (about 0.15 g), corners at about 0.2 g.
        s.speed.speed_mps = 3.0;
        s.speed.max_accel_mps2 = 1.5;
        s.speed.max_yaw_rate_deg_s = 30.0;
        s.speed.max_lateral_accel_mps2 = 2.0;
        s.sensor.mount_xyz = Eigen::Vector3d(0.0, 0.0, 0.2);  // on a roof rack
        s.path.mode = PathMode::kWaypoints;
    }
    return s;
}

std::string_view ToString(Platform platform) {
    switch (platform) {
        case Platform::kGo1:
            return "go1";
        case Platform::kHandheld:
            return "handheld";
        case Platform::kVehicle:
            return "vehicle";
    }
    return "?";
}

std::string_view ToString(PathMode mode) {
    switch (mode) {
        case PathMode::kCoverage:
            return "coverage";
        case PathMode::kWaypoints:
            return "waypoints";
    }
    return "?";
}

std::optional<Platform> PlatformFromString(std::string_view text) {
    for (const Platform p : {Platform::kGo1, Platform::kHandheld, Platform::kVehicle}) {
        if (text == ToString(p)) return p;
    }
    return std::nullopt;
}

std::optional<PathMode> PathModeFromString(std::string_view text) {
    for (const PathMode m : {PathMode::kCoverage, PathMode::kWaypoints}) {
        if (text == ToString(m)) return m;
    }
    return std::nullopt;
}

std::string ItemPath(const std::string& path, size_t i) {
    return path + "[" + std::to_string(i) + "]";
}

}  // namespace bimslam::simulate
