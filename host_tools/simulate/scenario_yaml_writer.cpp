// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Scenario to YAML (scenario_yaml.hpp): every field, numbers in their shortest exact form, so
// that ParseScenario (scenario_yaml.cpp) reads back an equal scenario.
#include <yaml-cpp/yaml.h>

#include <array>
#include <charconv>
#include <cmath>
#include <string>
#include <vector>

#include "host_tools/simulate/scenario_yaml.hpp"

namespace bimslam::simulate {
namespace {

// The shortest text that reads back to the same double.
std::string NumText(double x) {
    if (std::isnan(x)) return ".nan";
    if (std::isinf(x)) return x > 0 ? ".inf" : "-.inf";
    std::array<char, 32> buf{};
    const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), x);
    return std::string(buf.data(), r.ptr);
}

class Writer {
public:
    YAML::Emitter& out() { return out_; }
    Writer& Key(const char* key) {
        out_ << YAML::Key << key << YAML::Value;
        return *this;
    }
    void Num(const char* key, double x) { Key(key).out_ << NumText(x); }
    // Quoted always: a name such as "null", "1.5" or "yes" stays text.
    void Str(const char* key, const std::string& s) { Key(key).out_ << YAML::DoubleQuoted << s; }
    template <int N>
    void Vec(const char* key, const Eigen::Matrix<double, N, 1>& v) {
        Key(key);
        VecValue(v);
    }
    template <int N>
    void VecValue(const Eigen::Matrix<double, N, 1>& v) {
        out_ << YAML::Flow << YAML::BeginSeq;
        for (int i = 0; i < N; ++i) out_ << NumText(v[i]);
        out_ << YAML::EndSeq;
    }
    void StrList(const char* key, const std::vector<std::string>& list) {
        Key(key).out_ << YAML::Flow << YAML::BeginSeq;
        for (const auto& s : list) out_ << YAML::DoubleQuoted << s;
        out_ << YAML::EndSeq;
    }
    // A list of mappings, each written by `item`.
    template <typename T, typename F>
    void List(const char* key, const std::vector<T>& list, F&& item) {
        Key(key);
        if (list.empty()) out_ << YAML::Flow;  // "[]" on the key's line
        out_ << YAML::BeginSeq;
        for (const T& x : list) {
            out_ << YAML::BeginMap;
            item(x);
            out_ << YAML::EndMap;
        }
        out_ << YAML::EndSeq;
    }
    void BeginMap(const char* key) { Key(key).out_ << YAML::BeginMap; }
    void EndMap() { out_ << YAML::EndMap; }

private:
    YAML::Emitter out_;
};

// `in_visit`: a visit's edits, where removed.walk_through is on unless it says otherwise; at the
// top level it is written only when on, so the scenario.yaml of a capture made before it stays
// the same.
void WriteEdits(Writer& w, const EditsSpec& e, bool in_visit) {
    w.BeginMap("edits");
    w.List("boxes", e.boxes, [&](const AddedBox& b) {
        w.Str("name", b.name);
        w.Vec("center", b.center);
        w.Vec("size", b.size);
        w.Num("yaw_deg", b.yaw_deg);
    });
    w.List("cylinders", e.cylinders, [&](const AddedCylinder& c) {
        w.Str("name", c.name);
        w.Vec("base", c.base);
        w.Num("radius_m", c.radius_m);
        w.Num("height_m", c.height_m);
    });
    w.List("meshes", e.meshes, [&](const AddedMesh& m) {
        w.Str("name", m.name);
        w.Str("file", m.file.string());
        w.Vec("position", m.position);
        w.Num("yaw_deg", m.yaw_deg);
        w.Num("scale", m.scale);
    });
    w.BeginMap("clutter");
    w.Num("density_per_m2", e.clutter.density_per_m2);
    w.Num("min_size_m", e.clutter.min_size_m);
    w.Num("max_size_m", e.clutter.max_size_m);
    w.Num("keep_off_walk_m", e.clutter.keep_off_walk_m);
    w.EndMap();
    w.BeginMap("removed");
    w.StrList("global_ids", e.removed.global_ids);
    w.StrList("classes", e.removed.classes);
    if (in_visit || e.removed.walk_through) {
        w.Key("walk_through").out() << (e.removed.walk_through ? "true" : "false");
    }
    w.EndMap();
    w.List("moved", e.moved, [&](const MovedElement& m) {
        w.Str("global_id", m.global_id);
        w.Vec("translation", m.translation);
        w.Num("yaw_deg", m.yaw_deg);
    });
    w.BeginMap("as_built");
    w.Num("wall_offset_sigma_m", e.as_built.wall_offset_sigma_m);
    w.List("walls", e.as_built.walls, [&](const WallOffset& o) {
        w.Str("global_id", o.global_id);
        w.Num("offset_m", o.offset_m);
    });
    w.EndMap();
    w.List("people", e.people, [&](const PersonSpec& p) {
        w.Vec("from", p.from);
        w.Vec("to", p.to);
        w.Num("speed_mps", p.speed_mps);
        w.Num("radius_m", p.radius_m);
        w.Num("height_m", p.height_m);
    });
    w.Key("glass").out() << (e.glass ? "true" : "false");
    w.List("mirrors", e.mirrors, [&](const AddedMirror& m) {
        w.Str("name", m.name);
        w.Vec("center", m.center);
        w.Vec("size", m.size);
        w.Num("yaw_deg", m.yaw_deg);
    });
    w.BeginMap("moving_doors");
    w.StrList("global_ids", e.moving_doors.global_ids);
    w.StrList("classes", e.moving_doors.classes);
    w.Num("period_s", e.moving_doors.period_s);
    w.Num("max_angle_deg", e.moving_doors.max_angle_deg);
    w.EndMap();
    w.EndMap();
}

void WritePath(Writer& w, const PathSpec& path) {
    w.BeginMap("path");
    w.Key("mode").out() << std::string(ToString(path.mode));
    w.Key("waypoints").out() << YAML::Flow << YAML::BeginSeq;
    for (const auto& p : path.waypoints) w.VecValue(p);
    w.out() << YAML::EndSeq;
    if (!path.waypoint_storeys.empty()) w.StrList("waypoint_storeys", path.waypoint_storeys);
    if (path.start) {
        w.BeginMap("start");
        w.Vec("xy", path.start->xy);
        w.Num("yaw_deg", path.start->yaw_deg);
        w.EndMap();
    }
    w.EndMap();
}

// Each visit with the keys it sets (the others are the top level's).
void WriteVisits(Writer& w, const std::vector<VisitSpec>& visits) {
    w.List("visits", visits, [&](const VisitSpec& v) {
        w.Str("label", v.label);
        w.Str("date", v.date);
        if (v.platform) w.Key("platform").out() << std::string(ToString(*v.platform));
        if (v.seed) w.Key("seed").out() << std::to_string(*v.seed);
        if (v.path) WritePath(w, *v.path);
        if (v.duration_s) w.Num("duration_s", *v.duration_s);
        if (v.storey) w.Str("storey", *v.storey);
        if (v.edits) WriteEdits(w, *v.edits, /*in_visit=*/true);
    });
}

}  // namespace

std::string ScenarioToYaml(const Scenario& s) {
    Writer w;
    YAML::Emitter& out = w.out();
    out << YAML::BeginMap;
    w.Str("model", s.model.string());
    w.Str("storey", s.storey);
    w.Key("platform").out() << std::string(ToString(s.platform));

    WritePath(w, s.path);

    w.BeginMap("speed");
    w.Num("speed_mps", s.speed.speed_mps);
    w.Num("max_accel_mps2", s.speed.max_accel_mps2);
    w.Num("max_yaw_rate_deg_s", s.speed.max_yaw_rate_deg_s);
    w.Num("max_lateral_accel_mps2", s.speed.max_lateral_accel_mps2);
    w.Key("start_at_speed").out() << (s.speed.start_at_speed ? "true" : "false");
    w.EndMap();
    w.Num("duration_s", s.duration_s);

    w.BeginMap("sensor");
    w.Str("metadata", s.sensor.metadata.string());
    w.Str("model", s.sensor.model);
    w.Str("lidar_mode", s.sensor.lidar_mode);
    w.Str("udp_profile", s.sensor.udp_profile);
    w.Vec("mount_xyz", s.sensor.mount_xyz);
    w.Vec("mount_rpy_deg", s.sensor.mount_rpy_deg);
    w.Key("body_in_view").out() << (s.sensor.body_in_view ? "true" : "false");
    w.Num("clock_jump_at_s", s.sensor.clock_jump_at_s);
    w.Num("clock_jump_s", s.sensor.clock_jump_s);
    w.EndMap();

    w.BeginMap("network");
    w.Key("fragment").out() << (s.network.fragment ? "true" : "false");
    w.Num("packet_loss", s.network.packet_loss);
    w.Str("go1_highstate_crc", go1::ToString(s.network.go1_highstate_crc));
    w.EndMap();

    const NoiseSpec& n = s.noise;
    w.BeginMap("noise");
    w.BeginMap("lidar");
    w.Num("range_sigma_m", n.lidar.range_sigma_m);
    w.Num("dropout", n.lidar.dropout);
    w.Num("max_range_m", n.lidar.max_range_m);
    w.Num("glass_return_probability", n.lidar.glass_return_probability);
    w.Num("glass_return_exponent", n.lidar.glass_return_exponent);
    w.EndMap();
    w.BeginMap("imu");
    w.Num("accel_sigma_mps2", n.imu.accel_sigma_mps2);
    w.Num("gyro_sigma_deg_s", n.imu.gyro_sigma_deg_s);
    w.Num("accel_bias_sigma_mps2", n.imu.accel_bias_sigma_mps2);
    w.Num("gyro_bias_sigma_deg_s", n.imu.gyro_bias_sigma_deg_s);
    w.EndMap();
    w.BeginMap("odometry");
    w.Num("scale_error", n.odometry.scale_error);
    w.Num("velocity_sigma_mps", n.odometry.velocity_sigma_mps);
    w.Num("yaw_drift_deg_per_min", n.odometry.yaw_drift_deg_per_min);
    w.Num("slips_per_min", n.odometry.slips_per_min);
    w.Num("slip_duration_s", n.odometry.slip_duration_s);
    w.Num("slip_factor", n.odometry.slip_factor);
    w.EndMap();
    w.EndMap();

    w.Key("seed").out() << std::to_string(s.seed);
    if (!s.date.empty()) w.Str("date", s.date);
    WriteEdits(w, s.edits, /*in_visit=*/false);
    if (!s.visits.empty()) WriteVisits(w, s.visits);
    out << YAML::EndMap;
    return std::string(out.c_str()) + "\n";
}

}  // namespace bimslam::simulate
