#include "host_tools/simulate/scenario_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <map>
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
std::string Idx(const std::string& path, size_t i) { return path + "[" + std::to_string(i) + "]"; }

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
        for (int i = 0; i < N; ++i) Read(n[i], Idx(path, i), out[i]);
    }
    void Read(const Node& n, const std::string& path, Platform& out) const {
        std::string s;
        Read(n, path, s);
        const auto p = PlatformFromString(s);
        if (!p) Fail(n, path + ": expected go1 or handheld, got " + Describe(n));
        out = *p;
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
            lines_[Idx(path, i)] = Line(n[i]);
            Read(n[i], Idx(path, i), out[i]);
        }
    }

    void Read(const Node& n, const std::string& p, Pose2d& out);
    void Read(const Node& n, const std::string& p, AddedBox& out);
    void Read(const Node& n, const std::string& p, AddedCylinder& out);
    void Read(const Node& n, const std::string& p, AddedMesh& out);
    void Read(const Node& n, const std::string& p, MovedElement& out);
    void Read(const Node& n, const std::string& p, WallOffset& out);
    void Read(const Node& n, const std::string& p, PersonSpec& out);

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

void ReadNoise(Reader& r, const Node& n, NoiseSpec& out) {
    r.Keys(n, "noise", {"lidar", "imu", "odometry"});
    const Node lidar = Reader::At(n, "lidar");
    r.Keys(lidar, "noise.lidar", {"range_sigma_m", "dropout", "max_range_m"});
    r.Get(lidar, "noise.lidar", "range_sigma_m", out.lidar.range_sigma_m);
    r.Get(lidar, "noise.lidar", "dropout", out.lidar.dropout);
    r.Get(lidar, "noise.lidar", "max_range_m", out.lidar.max_range_m);
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

void ReadEdits(Reader& r, const Node& n, EditsSpec& out) {
    r.Keys(n, "edits",
           {"boxes", "cylinders", "meshes", "clutter", "removed", "moved", "as_built", "people"});
    r.Get(n, "edits", "boxes", out.boxes);
    r.Get(n, "edits", "cylinders", out.cylinders);
    r.Get(n, "edits", "meshes", out.meshes);
    const Node clutter = Reader::At(n, "clutter");
    const std::string c = "edits.clutter";
    r.Keys(clutter, c, {"density_per_m2", "min_size_m", "max_size_m", "keep_off_walk_m"});
    r.Get(clutter, c, "density_per_m2", out.clutter.density_per_m2);
    r.Get(clutter, c, "min_size_m", out.clutter.min_size_m);
    r.Get(clutter, c, "max_size_m", out.clutter.max_size_m);
    r.Get(clutter, c, "keep_off_walk_m", out.clutter.keep_off_walk_m);
    const Node removed = Reader::At(n, "removed");
    r.Keys(removed, "edits.removed", {"global_ids", "classes"});
    r.Get(removed, "edits.removed", "global_ids", out.removed.global_ids);
    r.Get(removed, "edits.removed", "classes", out.removed.classes);
    r.Get(n, "edits", "moved", out.moved);
    const Node as_built = Reader::At(n, "as_built");
    r.Keys(as_built, "edits.as_built", {"wall_offset_sigma_m", "walls"});
    r.Get(as_built, "edits.as_built", "wall_offset_sigma_m", out.as_built.wall_offset_sigma_m);
    r.Get(as_built, "edits.as_built", "walls", out.as_built.walls);
    r.Get(n, "edits", "people", out.people);
}

Scenario ReadScenario(Reader& r, const Node& root) {
    r.Keys(root, "",
           {"model", "storey", "platform", "path", "speed", "duration_s", "sensor", "network",
            "noise", "seed", "edits"});
    // The platform picks the defaults the other keys overlay.
    Platform platform = Platform::kGo1;
    r.Get(root, "", "platform", platform);
    Scenario s = DefaultScenario(platform);
    r.Get(root, "", "model", s.model);
    r.Get(root, "", "storey", s.storey);

    const Node path = Reader::At(root, "path");
    r.Keys(path, "path", {"mode", "waypoints", "start"});
    r.Get(path, "path", "mode", s.path.mode);
    r.Get(path, "path", "waypoints", s.path.waypoints);
    // `start: ~` clears it (no start: the walk's own first point).
    if (const Node start = Reader::At(path, "start"); start.IsDefined()) {
        s.path.start.reset();
        if (!start.IsNull()) r.Read(start, "path.start", s.path.start.emplace());
    }

    const Node speed = Reader::At(root, "speed");
    r.Keys(speed, "speed",
           {"speed_mps", "max_accel_mps2", "max_yaw_rate_deg_s", "max_lateral_accel_mps2"});
    r.Get(speed, "speed", "speed_mps", s.speed.speed_mps);
    r.Get(speed, "speed", "max_accel_mps2", s.speed.max_accel_mps2);
    r.Get(speed, "speed", "max_yaw_rate_deg_s", s.speed.max_yaw_rate_deg_s);
    r.Get(speed, "speed", "max_lateral_accel_mps2", s.speed.max_lateral_accel_mps2);
    r.Get(root, "", "duration_s", s.duration_s);

    const Node sensor = Reader::At(root, "sensor");
    r.Keys(sensor, "sensor",
           {"metadata", "lidar_mode", "udp_profile", "mount_xyz", "mount_rpy_deg"});
    r.Get(sensor, "sensor", "metadata", s.sensor.metadata);
    r.Get(sensor, "sensor", "lidar_mode", s.sensor.lidar_mode);
    r.Get(sensor, "sensor", "udp_profile", s.sensor.udp_profile);
    r.Get(sensor, "sensor", "mount_xyz", s.sensor.mount_xyz);
    r.Get(sensor, "sensor", "mount_rpy_deg", s.sensor.mount_rpy_deg);

    const Node network = Reader::At(root, "network");
    r.Keys(network, "network", {"fragment", "packet_loss"});
    r.Get(network, "network", "fragment", s.network.fragment);
    r.Get(network, "network", "packet_loss", s.network.packet_loss);

    ReadNoise(r, Reader::At(root, "noise"), s.noise);
    r.Get(root, "", "seed", s.seed);
    ReadEdits(r, Reader::At(root, "edits"), s.edits);
    return s;
}

// ---- writing ----

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

void WriteEdits(Writer& w, const EditsSpec& e) {
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
    w.EndMap();
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

std::string ScenarioToYaml(const Scenario& s) {
    Writer w;
    YAML::Emitter& out = w.out();
    out << YAML::BeginMap;
    w.Str("model", s.model.string());
    w.Str("storey", s.storey);
    w.Key("platform").out() << std::string(ToString(s.platform));

    w.BeginMap("path");
    w.Key("mode").out() << std::string(ToString(s.path.mode));
    w.Key("waypoints").out() << YAML::Flow << YAML::BeginSeq;
    for (const auto& p : s.path.waypoints) w.VecValue(p);
    out << YAML::EndSeq;
    if (s.path.start) {
        w.BeginMap("start");
        w.Vec("xy", s.path.start->xy);
        w.Num("yaw_deg", s.path.start->yaw_deg);
        w.EndMap();
    }
    w.EndMap();

    w.BeginMap("speed");
    w.Num("speed_mps", s.speed.speed_mps);
    w.Num("max_accel_mps2", s.speed.max_accel_mps2);
    w.Num("max_yaw_rate_deg_s", s.speed.max_yaw_rate_deg_s);
    w.Num("max_lateral_accel_mps2", s.speed.max_lateral_accel_mps2);
    w.EndMap();
    w.Num("duration_s", s.duration_s);

    w.BeginMap("sensor");
    w.Str("metadata", s.sensor.metadata.string());
    w.Str("lidar_mode", s.sensor.lidar_mode);
    w.Str("udp_profile", s.sensor.udp_profile);
    w.Vec("mount_xyz", s.sensor.mount_xyz);
    w.Vec("mount_rpy_deg", s.sensor.mount_rpy_deg);
    w.EndMap();

    w.BeginMap("network");
    w.Key("fragment").out() << (s.network.fragment ? "true" : "false");
    w.Num("packet_loss", s.network.packet_loss);
    w.EndMap();

    const NoiseSpec& n = s.noise;
    w.BeginMap("noise");
    w.BeginMap("lidar");
    w.Num("range_sigma_m", n.lidar.range_sigma_m);
    w.Num("dropout", n.lidar.dropout);
    w.Num("max_range_m", n.lidar.max_range_m);
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
    WriteEdits(w, s.edits);
    out << YAML::EndMap;
    return std::string(out.c_str()) + "\n";
}

}  // namespace bimslam::simulate
