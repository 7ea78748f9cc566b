// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/simulate/scenario_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>
#include <utility>

#include "algorithms/common/status.hpp"

namespace bimslam::simulate {
namespace {

namespace fs = std::filesystem;
using common::FileError;
using common::StatusCode;
using Node = YAML::Node;

std::string Join(const std::string& path, std::string_view key) {
    return path.empty() ? std::string(key) : path + "." + std::string(key);
}
// What a node holds, for "expected X, got Y".
std::string Describe(const Node& n) {
    if (n.IsScalar()) return "'" + n.Scalar() + "'";
    if (n.IsSequence()) return "a sequence of " + std::to_string(n.size());
    if (n.IsMap()) return "a mapping";
    return "nothing";
}

// Reads the parts of a scenario, remembering the line of every key path it read so that a
// Validate() error (which names the key path) can point at its line too.
class Reader {
public:
    Reader(std::string name, fs::path base_dir)
        : name_(std::move(name)), base_dir_(std::move(base_dir)) {}

    [[noreturn]] void Fail(const Node& at, const std::string& message) const {
        throw FileError(StatusCode::kParseError, name_, Line(at), message);
    }

    // `node` must be a mapping (absent or null count as empty) whose keys are among `allowed`, each
    // once.
    void Keys(const Node& node, const std::string& path,
              std::initializer_list<std::string_view> allowed) {
        if (!node.IsDefined() || node.IsNull()) return;
        if (!node.IsMap()) {
            Fail(node, (path.empty() ? "the top level" : path) + ": expected a mapping, got " +
                           Describe(node));
        }
        std::set<std::string> seen;
        for (const auto& kv : node) {
            if (!kv.first.IsScalar()) Fail(kv.first, Join(path, "<key>") + ": keys must be words");
            const std::string key = kv.first.Scalar();
            bool known = false;
            std::string list;
            for (const auto a : allowed) {
                known = known || key == a;
                list += (list.empty() ? "" : ", ") + std::string(a);
            }
            if (!known) {
                Fail(kv.first, "unknown key '" + Join(path, key) + "' (allowed" +
                                   (path.empty() ? "" : " in '" + path + "'") + ": " + list + ")");
            }
            if (!seen.insert(key).second) Fail(kv.first, "duplicate key '" + Join(path, key) + "'");
            lines_[Join(path, key)] = Line(kv.first);
        }
    }

    // The value at map[key] when present (an undefined node otherwise). `map` may itself be
    // absent (yaml-cpp's "zombie" node, whose type may not even be asked).
    static Node At(const Node& map, std::string_view key) {
        return map.IsDefined() && map.IsMap() ? map[std::string(key)]
                                              : Node(YAML::NodeType::Undefined);
    }

    // Get(map, path, key, out): overwrites `out` when `key` is present.
    template <typename T>
    void Get(const Node& map, const std::string& path, std::string_view key, T& out) {
        const Node v = At(map, key);
        if (v.IsDefined()) Read(v, Join(path, key), out);
    }

    void Read(const Node& n, const std::string& path, double& out) const {
        if (!n.IsScalar()) Fail(n, path + ": expected a number, got " + Describe(n));
        std::string s = n.Scalar();
        // YAML's spellings of the non-finite values (Validate() then says what is wrong).
        if (s == ".inf" || s == ".Inf" || s == ".INF" || s == "+.inf") s = "inf";
        if (s == "-.inf" || s == "-.Inf" || s == "-.INF") s = "-inf";
        if (s == ".nan" || s == ".NaN" || s == ".NAN") s = "nan";
        const char* begin = s.data();
        const char* end = begin + s.size();
        if (begin != end && *begin == '+') ++begin;
        const auto r = std::from_chars(begin, end, out);
        if (r.ec != std::errc() || r.ptr != end || begin == end) {
            Fail(n, path + ": expected a number, got " + Describe(n));
        }
    }
    void Read(const Node& n, const std::string& path, uint64_t& out) const {
        const std::string s = n.IsScalar() ? n.Scalar() : "";
        const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
        if (s.empty() || r.ec != std::errc() || r.ptr != s.data() + s.size()) {
            Fail(n, path + ": expected a whole number >= 0, got " + Describe(n));
        }
    }
    void Read(const Node& n, const std::string& path, bool& out) const {
        const std::string s = n.IsScalar() ? n.Scalar() : "";
        if (s == "true" || s == "True" || s == "TRUE") {
            out = true;
        } else if (s == "false" || s == "False" || s == "FALSE") {
            out = false;
        } else {
            Fail(n, path + ": expected true or false, got " + Describe(n));
        }
    }
    void Read(const Node& n, const std::string& path, std::string& out) const {
        if (n.IsNull()) {
            out.clear();
        } else if (n.IsScalar()) {
            out = n.Scalar();
        } else {
            Fail(n, path + ": expected a text, got " + Describe(n));
        }
    }
    void Read(const Node& n, const std::string& path, fs::path& out) const {
        std::string s;
        Read(n, path, s);
        out = s;
        if (!out.empty() && out.is_relative() && !base_dir_.empty()) {
            out = (base_dir_ / out).lexically_normal();
        }
    }
    template <int N>
    void Read(const Node& n, const std::string& path, Eigen::Matrix<double, N, 1>& out) const {
        if (!n.IsSequence() || n.size() != N) {
            Fail(n,
                 path + ": expected " + (N == 2 ? "[x, y]" : "[x, y, z]") + ", got " + Describe(n));
        }
        for (int i = 0; i < N; ++i) Read(n[i], ItemPath(path, i), out[i]);
    }
    void Read(const Node& n, const std::string& path, Platform& out) const {
        std::string s;
        Read(n, path, s);
        const auto p = PlatformFromString(s);
        if (!p) Fail(n, path + ": expected go1 or handheld, got " + Describe(n));
        out = *p;
    }
    void Read(const Node& n, const std::string& path, go1::CrcForm& out) const {
        std::string s;
        Read(n, path, s);
        if (s == go1::ToString(go1::CrcForm::kScrambled)) {
            out = go1::CrcForm::kScrambled;
        } else if (s == go1::ToString(go1::CrcForm::kPlain)) {
            out = go1::CrcForm::kPlain;
        } else {
            Fail(n, path + ": expected scrambled or plain, got " + Describe(n));
        }
    }
    void Read(const Node& n, const std::string& path, PathMode& out) const {
        std::string s;
        Read(n, path, s);
        const auto m = PathModeFromString(s);
        if (!m) Fail(n, path + ": expected coverage or waypoints, got " + Describe(n));
        out = *m;
    }
    // Lists replace the default list as a whole; each item is read from a fresh default.
    template <typename T>
    void Read(const Node& n, const std::string& path, std::vector<T>& out) {
        if (n.IsNull()) {
            out.clear();
            return;
        }
        if (!n.IsSequence()) Fail(n, path + ": expected a sequence, got " + Describe(n));
        out.assign(n.size(), T{});
        for (size_t i = 0; i < n.size(); ++i) {
            lines_[ItemPath(path, i)] = Line(n[i]);
            Read(n[i], ItemPath(path, i), out[i]);
        }
    }

    void Read(const Node& n, const std::string& p, Pose2d& out);
    void Read(const Node& n, const std::string& p, AddedBox& out);
    void Read(const Node& n, const std::string& p, AddedCylinder& out);
    void Read(const Node& n, const std::string& p, AddedMesh& out);
    void Read(const Node& n, const std::string& p, MovedElement& out);
    void Read(const Node& n, const std::string& p, WallOffset& out);
    void Read(const Node& n, const std::string& p, PersonSpec& out);
    void Read(const Node& n, const std::string& p, AddedMirror& out);

    // Remembers the line of a node that is not a key (a list's item).
    void Mark(const std::string& path, const Node& n) { lines_[path] = Line(n); }

    // The line of `path` or of the nearest enclosing key read; 0 when none.
    size_t LineOf(std::string path) const {
        while (!path.empty()) {
            if (const auto it = lines_.find(path); it != lines_.end()) return it->second;
            const size_t cut = path.find_last_of(".[");
            path.resize(cut == std::string::npos ? 0 : cut);
        }
        return 0;
    }

private:
    static size_t Line(const Node& n) {
        const YAML::Mark m = n.Mark();
        return m.is_null() ? 0 : static_cast<size_t>(m.line) + 1;
    }

    std::string name_;
    fs::path base_dir_;
    std::map<std::string, size_t> lines_;
};

void Reader::Read(const Node& n, const std::string& p, Pose2d& out) {
    Keys(n, p, {"xy", "yaw_deg"});
    Get(n, p, "xy", out.xy);
    Get(n, p, "yaw_deg", out.yaw_deg);
}
void Reader::Read(const Node& n, const std::string& p, AddedBox& out) {
    Keys(n, p, {"name", "center", "size", "yaw_deg"});
    Get(n, p, "name", out.name);
    Get(n, p, "center", out.center);
    Get(n, p, "size", out.size);
    Get(n, p, "yaw_deg", out.yaw_deg);
}
void Reader::Read(const Node& n, const std::string& p, AddedCylinder& out) {
    Keys(n, p, {"name", "base", "radius_m", "height_m"});
    Get(n, p, "name", out.name);
    Get(n, p, "base", out.base);
    Get(n, p, "radius_m", out.radius_m);
    Get(n, p, "height_m", out.height_m);
}
void Reader::Read(const Node& n, const std::string& p, AddedMesh& out) {
    Keys(n, p, {"name", "file", "position", "yaw_deg", "scale"});
    Get(n, p, "name", out.name);
    Get(n, p, "file", out.file);
    Get(n, p, "position", out.position);
    Get(n, p, "yaw_deg", out.yaw_deg);
    Get(n, p, "scale", out.scale);
}
void Reader::Read(const Node& n, const std::string& p, MovedElement& out) {
    Keys(n, p, {"global_id", "translation", "yaw_deg"});
    Get(n, p, "global_id", out.global_id);
    Get(n, p, "translation", out.translation);
    Get(n, p, "yaw_deg", out.yaw_deg);
}
void Reader::Read(const Node& n, const std::string& p, WallOffset& out) {
    Keys(n, p, {"global_id", "offset_m"});
    Get(n, p, "global_id", out.global_id);
    Get(n, p, "offset_m", out.offset_m);
}
void Reader::Read(const Node& n, const std::string& p, PersonSpec& out) {
    Keys(n, p, {"from", "to", "speed_mps", "radius_m", "height_m"});
    Get(n, p, "from", out.from);
    Get(n, p, "to", out.to);
    Get(n, p, "speed_mps", out.speed_mps);
    Get(n, p, "radius_m", out.radius_m);
    Get(n, p, "height_m", out.height_m);
}

void Reader::Read(const Node& n, const std::string& p, AddedMirror& out) {
    Keys(n, p, {"name", "center", "size", "yaw_deg"});
    Get(n, p, "name", out.name);
    Get(n, p, "center", out.center);
    Get(n, p, "size", out.size);
    Get(n, p, "yaw_deg", out.yaw_deg);
}

void ReadNoise(Reader& r, const Node& n, NoiseSpec& out) {
    r.Keys(n, "noise", {"lidar", "imu", "odometry"});
    const Node lidar = Reader::At(n, "lidar");
    r.Keys(lidar, "noise.lidar",
           {"range_sigma_m", "dropout", "max_range_m", "glass_return_probability",
            "glass_return_exponent"});
    r.Get(lidar, "noise.lidar", "range_sigma_m", out.lidar.range_sigma_m);
    r.Get(lidar, "noise.lidar", "dropout", out.lidar.dropout);
    r.Get(lidar, "noise.lidar", "max_range_m", out.lidar.max_range_m);
    r.Get(lidar, "noise.lidar", "glass_return_probability", out.lidar.glass_return_probability);
    r.Get(lidar, "noise.lidar", "glass_return_exponent", out.lidar.glass_return_exponent);
    const Node imu = Reader::At(n, "imu");
    r.Keys(
        imu, "noise.imu",
        {"accel_sigma_mps2", "gyro_sigma_deg_s", "accel_bias_sigma_mps2", "gyro_bias_sigma_deg_s"});
    r.Get(imu, "noise.imu", "accel_sigma_mps2", out.imu.accel_sigma_mps2);
    r.Get(imu, "noise.imu", "gyro_sigma_deg_s", out.imu.gyro_sigma_deg_s);
    r.Get(imu, "noise.imu", "accel_bias_sigma_mps2", out.imu.accel_bias_sigma_mps2);
    r.Get(imu, "noise.imu", "gyro_bias_sigma_deg_s", out.imu.gyro_bias_sigma_deg_s);
    const Node odo = Reader::At(n, "odometry");
    const std::string p = "noise.odometry";
    r.Keys(odo, p,
           {"scale_error", "velocity_sigma_mps", "yaw_drift_deg_per_min", "slips_per_min",
            "slip_duration_s", "slip_factor"});
    r.Get(odo, p, "scale_error", out.odometry.scale_error);
    r.Get(odo, p, "velocity_sigma_mps", out.odometry.velocity_sigma_mps);
    r.Get(odo, p, "yaw_drift_deg_per_min", out.odometry.yaw_drift_deg_per_min);
    r.Get(odo, p, "slips_per_min", out.odometry.slips_per_min);
    r.Get(odo, p, "slip_duration_s", out.odometry.slip_duration_s);
    r.Get(odo, p, "slip_factor", out.odometry.slip_factor);
}

// `at`: where the edits stand ("edits", or "visits[1].edits").
void ReadEdits(Reader& r, const Node& n, const std::string& at, EditsSpec& out) {
    r.Keys(n, at,
           {"boxes", "cylinders", "meshes", "clutter", "removed", "moved", "as_built", "people",
            "glass", "mirrors", "moving_doors"});
    r.Get(n, at, "boxes", out.boxes);
    r.Get(n, at, "cylinders", out.cylinders);
    r.Get(n, at, "meshes", out.meshes);
    const Node clutter = Reader::At(n, "clutter");
    const std::string c = at + ".clutter";
    r.Keys(clutter, c, {"density_per_m2", "min_size_m", "max_size_m", "keep_off_walk_m"});
    r.Get(clutter, c, "density_per_m2", out.clutter.density_per_m2);
    r.Get(clutter, c, "min_size_m", out.clutter.min_size_m);
    r.Get(clutter, c, "max_size_m", out.clutter.max_size_m);
    r.Get(clutter, c, "keep_off_walk_m", out.clutter.keep_off_walk_m);
    const Node removed = Reader::At(n, "removed");
    const std::string rm = at + ".removed";
    r.Keys(removed, rm, {"global_ids", "classes", "walk_through"});
    r.Get(removed, rm, "global_ids", out.removed.global_ids);
    r.Get(removed, rm, "classes", out.removed.classes);
    r.Get(removed, rm, "walk_through", out.removed.walk_through);
    r.Get(n, at, "moved", out.moved);
    const Node as_built = Reader::At(n, "as_built");
    const std::string ab = at + ".as_built";
    r.Keys(as_built, ab, {"wall_offset_sigma_m", "walls"});
    r.Get(as_built, ab, "wall_offset_sigma_m", out.as_built.wall_offset_sigma_m);
    r.Get(as_built, ab, "walls", out.as_built.walls);
    r.Get(n, at, "people", out.people);
    r.Get(n, at, "glass", out.glass);
    r.Get(n, at, "mirrors", out.mirrors);
    const Node doors = Reader::At(n, "moving_doors");
    const std::string d = at + ".moving_doors";
    r.Keys(doors, d, {"global_ids", "classes", "period_s", "max_angle_deg"});
    r.Get(doors, d, "global_ids", out.moving_doors.global_ids);
    r.Get(doors, d, "classes", out.moving_doors.classes);
    r.Get(doors, d, "period_s", out.moving_doors.period_s);
    r.Get(doors, d, "max_angle_deg", out.moving_doors.max_angle_deg);
}

// `at`: where the path stands ("path", or "visits[1].path").
void ReadPath(Reader& r, const Node& path, const std::string& at, PathSpec& out) {
    r.Keys(path, at, {"mode", "waypoints", "waypoint_storeys", "start"});
    r.Get(path, at, "mode", out.mode);
    r.Get(path, at, "waypoints", out.waypoints);
    r.Get(path, at, "waypoint_storeys", out.waypoint_storeys);
    // `start: ~` clears it (no start: the walk's own first point).
    if (const Node start = Reader::At(path, "start"); start.IsDefined()) {
        out.start.reset();
        if (!start.IsNull()) r.Read(start, at + ".start", out.start.emplace());
    }
}

// Reads map[key] into `out` when present.
template <typename T>
void GetOptional(Reader& r, const Node& map, const std::string& path, std::string_view key,
                 std::optional<T>& out) {
    if (Reader::At(map, key).IsDefined()) r.Get(map, path, key, out.emplace());
}

// The visits (VisitSpec): each item's keys, read as the top level's are. A visit's edits start
// from the defaults with removed.walk_through on: a wall demolished between visits opens the way.
void ReadVisits(Reader& r, const Node& n, std::vector<VisitSpec>& out) {
    out.clear();
    if (!n.IsDefined() || n.IsNull()) return;
    if (!n.IsSequence()) r.Fail(n, "visits: expected a sequence, got " + Describe(n));
    out.resize(n.size());
    for (size_t i = 0; i < n.size(); ++i) {
        const Node v = n[i];
        const std::string p = ItemPath("visits", i);
        r.Mark(p, v);
        if (!v.IsMap())
            r.Fail(v, p + ": expected a mapping (label, date, ...), got " + Describe(v));
        r.Keys(v, p,
               {"label", "date", "platform", "seed", "path", "duration_s", "storey", "edits"});
        VisitSpec& visit = out[i];
        r.Get(v, p, "label", visit.label);
        r.Get(v, p, "date", visit.date);
        GetOptional(r, v, p, "platform", visit.platform);
        GetOptional(r, v, p, "seed", visit.seed);
        GetOptional(r, v, p, "duration_s", visit.duration_s);
        GetOptional(r, v, p, "storey", visit.storey);
        if (const Node path = Reader::At(v, "path"); path.IsDefined()) {
            ReadPath(r, path, p + ".path", visit.path.emplace());
        }
        if (const Node edits = Reader::At(v, "edits"); edits.IsDefined()) {
            EditsSpec& e = visit.edits.emplace();
            e.removed.walk_through = true;
            ReadEdits(r, edits, p + ".edits", e);
        }
    }
}

Scenario ReadScenario(Reader& r, const Node& root) {
    r.Keys(root, "",
           {"model", "storey", "platform", "path", "speed", "duration_s", "sensor", "network",
            "noise", "seed", "date", "edits", "visits"});
    // The platform picks the defaults the other keys overlay.
    Platform platform = Platform::kGo1;
    r.Get(root, "", "platform", platform);
    Scenario s = DefaultScenario(platform);
    r.Get(root, "", "model", s.model);
    r.Get(root, "", "storey", s.storey);

    ReadPath(r, Reader::At(root, "path"), "path", s.path);

    const Node speed = Reader::At(root, "speed");
    r.Keys(speed, "speed",
           {"speed_mps", "max_accel_mps2", "max_yaw_rate_deg_s", "max_lateral_accel_mps2",
            "start_at_speed"});
    r.Get(speed, "speed", "speed_mps", s.speed.speed_mps);
    r.Get(speed, "speed", "max_accel_mps2", s.speed.max_accel_mps2);
    r.Get(speed, "speed", "max_yaw_rate_deg_s", s.speed.max_yaw_rate_deg_s);
    r.Get(speed, "speed", "max_lateral_accel_mps2", s.speed.max_lateral_accel_mps2);
    r.Get(speed, "speed", "start_at_speed", s.speed.start_at_speed);
    r.Get(root, "", "duration_s", s.duration_s);

    const Node sensor = Reader::At(root, "sensor");
    r.Keys(sensor, "sensor",
           {"metadata", "model", "lidar_mode", "udp_profile", "mount_xyz", "mount_rpy_deg",
            "body_in_view", "clock_jump_at_s", "clock_jump_s"});
    r.Get(sensor, "sensor", "metadata", s.sensor.metadata);
    r.Get(sensor, "sensor", "model", s.sensor.model);
    r.Get(sensor, "sensor", "lidar_mode", s.sensor.lidar_mode);
    r.Get(sensor, "sensor", "udp_profile", s.sensor.udp_profile);
    r.Get(sensor, "sensor", "mount_xyz", s.sensor.mount_xyz);
    r.Get(sensor, "sensor", "mount_rpy_deg", s.sensor.mount_rpy_deg);
    r.Get(sensor, "sensor", "body_in_view", s.sensor.body_in_view);
    r.Get(sensor, "sensor", "clock_jump_at_s", s.sensor.clock_jump_at_s);
    r.Get(sensor, "sensor", "clock_jump_s", s.sensor.clock_jump_s);

    const Node network = Reader::At(root, "network");
    r.Keys(network, "network", {"fragment", "packet_loss", "go1_highstate_crc"});
    r.Get(network, "network", "fragment", s.network.fragment);
    r.Get(network, "network", "packet_loss", s.network.packet_loss);
    r.Get(network, "network", "go1_highstate_crc", s.network.go1_highstate_crc);

    ReadNoise(r, Reader::At(root, "noise"), s.noise);
    r.Get(root, "", "seed", s.seed);
    r.Get(root, "", "date", s.date);
    ReadEdits(r, Reader::At(root, "edits"), "edits", s.edits);
    ReadVisits(r, Reader::At(root, "visits"), s.visits);
    return s;
}

}  // namespace

Scenario ParseScenario(const std::string& name, const std::string& text, const fs::path& base_dir) {
    Node root;
    try {
        root = YAML::Load(text);
    } catch (const YAML::Exception& e) {
        const size_t line = e.mark.is_null() ? 0 : static_cast<size_t>(e.mark.line) + 1;
        const std::string column =
            e.mark.is_null() ? "" : ", column " + std::to_string(e.mark.column + 1);
        throw FileError(StatusCode::kParseError, name, line,
                        "YAML syntax error" + column + ": " + e.msg);
    }
    Reader reader(name, base_dir);
    Scenario s;
    try {
        s = ReadScenario(reader, root);
    } catch (const YAML::Exception& e) {  // not expected: the reader checks types first
        throw FileError(StatusCode::kParseError, name,
                        e.mark.is_null() ? 0 : static_cast<size_t>(e.mark.line) + 1, e.msg);
    }
    try {
        s.Validate();
    } catch (const common::Error& e) {
        // The message starts with the key path ("speed.speed_mps = -1: ..."): point at its line.
        const std::string message = e.what();
        const size_t eq = message.find(" = ");
        const size_t line = eq == std::string::npos ? 0 : reader.LineOf(message.substr(0, eq));
        throw FileError(e.code(), name, line, message);
    }
    return s;
}

Scenario LoadScenario(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw FileError(StatusCode::kNotFound, file.string(), 0, "cannot open scenario file");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw FileError(StatusCode::kIoError, file.string(), 0, "cannot read");
    // Absolute, so the paths it names stay right whatever the working folder is later.
    return ParseScenario(file.string(), text.str(),
                         fs::absolute(file).lexically_normal().parent_path());
}

}  // namespace bimslam::simulate
