// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "firmware/app/rig_config.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

#include "algorithms/common/status.hpp"
#include "algorithms/localization/loop_rules.hpp"

namespace bimslam::rig {
namespace {
using common::FileError;
using common::StatusCode;

// A key of the schema bound to its field of one RigConfig.
struct Binding {
    ConfigKey key;
    // Applies a YAML value; returns "" or what is wrong with it.
    std::function<std::string(const YAML::Node&)> set;
    std::function<std::string()> print;
};

std::string Num(double v) {
    std::ostringstream s;
    s << std::setprecision(10) << v;
    return s.str();
}

Binding Int(const std::string& path, int& field, int lo, int hi, const std::string& unit,
            const std::string& doc) {
    return {{path, "int", unit, "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]", doc},
            [&field, lo, hi](const YAML::Node& n) -> std::string {
                long long v = 0;
                try {
                    v = n.as<long long>();
                } catch (const YAML::Exception&) {
                    return "expected an integer, got '" + n.Scalar() + "'";
                }
                if (v < lo || v > hi) {
                    return std::to_string(v) + " is out of range [" + std::to_string(lo) + ", " +
                           std::to_string(hi) + "]";
                }
                field = static_cast<int>(v);
                return "";
            },
            [&field] { return std::to_string(field); }};
}

Binding Real(const std::string& path, double& field, double lo, double hi, const std::string& unit,
             const std::string& doc) {
    return {{path, "number", unit, "[" + Num(lo) + ", " + Num(hi) + "]", doc},
            [&field, lo, hi](const YAML::Node& n) -> std::string {
                double v = 0;
                try {
                    v = n.as<double>();
                } catch (const YAML::Exception&) {
                    return "expected a number, got '" + n.Scalar() + "'";
                }
                if (!std::isfinite(v) || v < lo || v > hi) {
                    return Num(v) + " is out of range [" + Num(lo) + ", " + Num(hi) + "]";
                }
                field = v;
                return "";
            },
            [&field] { return Num(field); }};
}

Binding Bool(const std::string& path, bool& field, const std::string& doc) {
    return {{path, "bool", "", "true | false", doc},
            [&field](const YAML::Node& n) -> std::string {
                try {
                    field = n.as<bool>();
                } catch (const YAML::Exception&) {
                    return "expected true or false, got '" + n.Scalar() + "'";
                }
                return "";
            },
            [&field] { return std::string(field ? "true" : "false"); }};
}

Binding Text(const std::string& path, std::string& field, const std::string& doc) {
    return {{path, "string", "", "text", doc},
            [&field](const YAML::Node& n) -> std::string {
                field = n.Scalar();
                return "";
            },
            [&field] { return "\"" + field + "\""; }};
}

Binding Enum(const std::string& path, std::string& field, const std::vector<std::string>& values,
             const std::string& doc) {
    std::string range;
    for (const std::string& v : values) range += (range.empty() ? "" : " | ") + v;
    return {{path, "enum", "", range, doc},
            [&field, values, range](const YAML::Node& n) -> std::string {
                for (const std::string& v : values) {
                    if (n.Scalar() == v) {
                        field = v;
                        return "";
                    }
                }
                return "'" + n.Scalar() + "' is not one of " + range;
            },
            [&field] { return field; }};
}

// The numbers of a YAML list into *out: "" or what is wrong.
std::string Numbers(const YAML::Node& node, std::vector<double>* out) {
    out->clear();
    for (const YAML::Node& x : node) {
        try {
            out->push_back(x.as<double>());
        } catch (const YAML::Exception&) {
            return "expected numbers, got '" + x.Scalar() + "'";
        }
        if (!std::isfinite(out->back())) return "a value is not finite";
    }
    return "";
}

Binding Vector(const std::string& path, std::vector<double>& field, size_t n,
               const std::string& unit, const std::string& doc) {
    return {{path, "vector", unit, std::to_string(n) + " numbers", doc},
            [&field, n](const YAML::Node& node) -> std::string {
                if (!node.IsSequence() || node.size() != n) {
                    return "expected a list of " + std::to_string(n) + " numbers";
                }
                std::vector<double> v;
                const std::string wrong = Numbers(node, &v);
                if (wrong.empty()) field = v;
                return wrong;
            },
            [&field] {
                std::string s = "[";
                for (size_t i = 0; i < field.size(); ++i) s += (i ? ", " : "") + Num(field[i]);
                return s + "]";
            }};
}

// Where the walk starts: [x, y] or [x, y, radius] (localization::StartHint's checks), or [] for
// none.
Binding Near(const std::string& path, std::vector<double>& field, const std::string& doc) {
    Binding b = Vector(path, field, 3, "m", doc);
    b.key.range = "[] | [x, y] | [x, y, radius]";
    b.set = [&field](const YAML::Node& node) -> std::string {
        if (!node.IsSequence() || (node.size() != 0 && node.size() != 2 && node.size() != 3)) {
            return "expected [], [x, y] or [x, y, radius]";
        }
        std::vector<double> v;
        if (const std::string wrong = Numbers(node, &v); !wrong.empty()) return wrong;
        if (!v.empty()) {
            try {
                localization::StartHint::FromList(v);
            } catch (const common::Error& e) {
                return e.what();
            }
        }
        field = v;
        return "";
    };
    return b;
}

void ThreadKeys(std::vector<Binding>& b, const std::string& name, ThreadConfig& t) {
    b.push_back(Int("threads." + name + ".priority", t.priority, 0, 99, "",
                    "SCHED_FIFO priority; 0: the normal scheduler"));
    b.push_back(Int("threads." + name + ".cpu", t.cpu, -1, 1023, "",
                    "CPU the thread is pinned to; -1: any"));
}

std::vector<Binding> Bindings(RigConfig& c) {
    std::vector<Binding> b;
    b.push_back(Text("sensor.metadata", c.metadata, "the Ouster's metadata JSON (live mode)"));
    b.push_back(Text("sensor.address", c.sensor_address,
                     "accept packets from this IPv4 address only; \"\": from any"));
    b.push_back(Text("sensor.bind_address", c.bind_address, "local IPv4 address to listen on"));
    b.push_back(
        Int("sensor.lidar_port", c.lidar_port, 0, 65535, "", "lidar UDP port; 0: the metadata's"));
    b.push_back(
        Int("sensor.imu_port", c.imu_port, 0, 65535, "", "IMU UDP port; 0: the metadata's"));
    b.push_back(Int("sensor.receive_buffer_bytes", c.receive_buffer_bytes, 0, 1 << 30, "B",
                    "SO_RCVBUF request of each socket"));
    b.push_back(Real("sensor.timeout_s", c.sensor_timeout_s, 0.05, 60, "s",
                     "no lidar packet for this long is a fault"));
    b.push_back(Enum("can.source", c.can_source, {"socketcan", "lcm", "log", "none"},
                     "where the Go1 CAN frames come from"));
    b.push_back(
        Text("can.interface", c.can_interface, "SocketCAN interface (can.source socketcan)"));
    b.push_back(Text("can.log", c.can_log, "candump -l log or CAN pcap (can.source log)"));
    b.push_back(Text("can.lcm_channel", c.can_lcm_channel,
                     "can_frame_t channel of bimslam-go1-bridge --lcm (can.source lcm)"));
    b.push_back(Real("can.wait_ms", c.can_wait_ms, 0, 1000, "ms",
                     "how long a scan waits for the CAN ingest to reach its time"));
    b.push_back(Real("odometry.budget_ms", c.budget_ms, 1, 1000, "ms", "time budget per scan"));
    b.push_back(Real("odometry.deadline_ms", c.deadline_ms, 1, 10000, "ms",
                     "from a frame's last packet to its odometry message"));
    b.push_back(Bool("odometry.use_imu", c.use_imu, "the Ouster IMU's gyro for deskew and prior"));
    b.push_back(Bool("odometry.deskew", c.deskew, "motion-compensate scans"));
    b.push_back(Bool("odometry.edge_features", c.edge_features, "LOAM edge features too"));
    b.push_back(Vector("odometry.mount", c.mount, 6, "m, deg",
                       "T_base_lidar: x y z roll pitch yaw of the lidar on the Go1's body"));
    b.push_back(Real("keyframes.distance_m", c.keyframe_distance_m, 0.05, 100, "m",
                     "a keyframe every this much travel"));
    b.push_back(Real("keyframes.angle_deg", c.keyframe_angle_deg, 0.5, 180, "deg",
                     "or every this much rotation"));
    b.push_back(Bool("session.record", c.record, "write a session"));
    b.push_back(Text("session.root", c.session_root, "folder of the sessions (one per start)"));
    b.push_back(Real("session.min_free_mb", c.min_free_mb, 0, 1e9, "MB",
                     "below this free space no more keyframe clouds are written"));
    b.push_back(Text("lcm.url", c.lcm_url, "LCM provider URL"));
    b.push_back(Bool("lcm.publish_keyframes", c.publish_keyframes, "BIMSLAM_KEYFRAME"));
    b.push_back(Bool("lcm.publish_imu", c.publish_imu, "BIMSLAM_IMU"));
    b.push_back(Bool("lcm.publish_go1_state", c.publish_go1_state, "BIMSLAM_GO1_STATE"));
    b.push_back(Real("lcm.replay_rate_mb_s", c.lcm_replay_rate_mb_s, 1, 10000, "MB/s",
                     "a replay's LCM output is held to this rate so that receivers keep up; "
                     "live runs are never paced"));
    b.push_back(Real("lcm.replay_messages_per_s", c.lcm_replay_messages_per_s, 10, 1e6, "1/s",
                     "and to this many messages a second"));
    b.push_back(Int("queues.scans", c.scan_queue, 1, 64, "items", "ingest -> odometry"));
    b.push_back(Int("queues.imu", c.imu_queue, 16, 65536, "items", "Ouster IMU -> odometry"));
    b.push_back(Int("queues.body", c.body_queue, 16, 65536, "items", "Go1 samples -> odometry"));
    b.push_back(Int("queues.publish", c.publish_queue, 8, 65536, "items", "messages -> LCM"));
    b.push_back(Int("queues.keyframes", c.keyframe_queue, 1, 256, "items",
                    "keyframes -> session writer and LCM"));
    b.push_back(Text("localization.map", c.bim_map,
                     "the building's map package (bimslam rig-map); \"\": none. A package "
                     "missing, damaged or of another model is refused (FAULT_BIM_MAP) and the rig "
                     "maps in its own frame"));
    b.push_back(Text("localization.model_sha256", c.bim_model_sha256,
                     "SHA-256 (hex) of the IFC model the package must be of; \"\": any"));
    b.push_back(Real("localization.deadline_ms", c.localizer_deadline_ms, 10, 60000, "ms",
                     "a keyframe's relocalisation (CPU time) longer than this is a deadline miss"));
    b.push_back(Real("localization.lost_fault_s", c.bim_lost_fault_s, 1, 3600, "s",
                     "not localised this long after a localisation: FAULT_BIM_LOST"));
    b.push_back(Near("localization.near", c.bim_near,
                     "where the walk starts, model metres (radius 3 m when absent): hypotheses "
                     "that put the rig's start farther away are set aside. For buildings of "
                     "identical parts, where the rig is otherwise ambiguous"));
    b.push_back(Bool("runtime.lock_memory", c.lock_memory, "mlockall at start"));
    ThreadKeys(b, "ingest", c.ingest);
    ThreadKeys(b, "can", c.can);
    ThreadKeys(b, "odometry", c.odometry);
    ThreadKeys(b, "writer", c.writer);
    ThreadKeys(b, "lcm", c.lcm);
    ThreadKeys(b, "health", c.health);
    ThreadKeys(b, "localizer", c.localizer);
    b.push_back(Real("health.period_s", c.health_period_s, 0.1, 10, "s",
                     "rig health, Ouster stats, watchdog and fault logs"));
    b.push_back(Real("health.log_interval_s", c.log_interval_s, 0.1, 3600, "s",
                     "the same fault is logged at most this often"));
    return b;
}

std::string NodeKind(const YAML::Node& n) {
    switch (n.Type()) {
        case YAML::NodeType::Map:
            return "a map";
        case YAML::NodeType::Sequence:
            return "a list";
        case YAML::NodeType::Null:
            return "nothing";
        default:
            return "'" + n.Scalar() + "'";
    }
}

}  // namespace

const std::vector<ConfigKey>& ConfigSchema() {
    static const std::vector<ConfigKey> keys = [] {
        RigConfig c;
        std::vector<ConfigKey> k;
        for (const Binding& b : Bindings(c)) k.push_back(b.key);
        return k;
    }();
    return keys;
}

void LoadConfigFile(const std::filesystem::path& path, RigConfig& config) {
    std::ifstream in(path);
    if (!in) throw FileError(StatusCode::kNotFound, path.string(), 0, "cannot open");
    YAML::Node root;
    try {
        root = YAML::Load(in);
    } catch (const YAML::Exception& e) {
        throw FileError(StatusCode::kParseError, path.string(), size_t(e.mark.line + 1), e.msg);
    }
    if (root.IsNull()) return;  // an empty file: the defaults
    if (!root.IsMap()) {
        throw FileError(StatusCode::kParseError, path.string(), size_t(root.Mark().line + 1),
                        "expected a map of sections (sensor, can, odometry, ...)");
    }
    std::vector<Binding> bindings = Bindings(config);
    std::map<std::string, Binding*> by_path;
    std::map<std::string, bool> sections;
    for (Binding& b : bindings) {
        by_path[b.key.path] = &b;
        for (size_t dot = b.key.path.find('.'); dot != std::string::npos;
             dot = b.key.path.find('.', dot + 1)) {
            sections[b.key.path.substr(0, dot)] = true;
        }
    }
    // Depth first, so that the error names the full path.
    std::function<void(const YAML::Node&, const std::string&)> walk =
        [&](const YAML::Node& map, const std::string& prefix) {
            for (const auto& kv : map) {
                const std::string key = prefix + kv.first.Scalar();
                const size_t line = size_t(kv.first.Mark().line + 1);
                if (sections.count(key)) {
                    if (!kv.second.IsMap()) {
                        throw FileError(StatusCode::kParseError, path.string(), line,
                                        key + ": expected a map, got " + NodeKind(kv.second));
                    }
                    walk(kv.second, key + ".");
                    continue;
                }
                const auto it = by_path.find(key);
                if (it == by_path.end()) {
                    throw FileError(StatusCode::kParseError, path.string(), line,
                                    key + ": unknown key (bimslam-rig --print-config lists them)");
                }
                if (it->second->key.type != "vector" && !kv.second.IsScalar()) {
                    throw FileError(StatusCode::kParseError, path.string(), line,
                                    key + ": expected a " + it->second->key.type + ", got " +
                                        NodeKind(kv.second));
                }
                const std::string error = it->second->set(kv.second);
                if (!error.empty()) {
                    throw FileError(StatusCode::kOutOfRange, path.string(), line,
                                    key + ": " + error);
                }
            }
        };
    walk(root, "");
}

void ValidateConfig(const RigConfig& c) {
    if (c.can_source == "log" && c.can_log.empty() && !c.handheld) {
        throw common::Error(StatusCode::kInvalidArgument,
                            "can.source is log but can.log names no file");
    }
    if (c.budget_ms >= c.deadline_ms) {
        throw common::Error(StatusCode::kInvalidArgument,
                            "odometry.budget_ms (" + Num(c.budget_ms) +
                                ") must be below odometry.deadline_ms (" + Num(c.deadline_ms) +
                                ")");
    }
    if (c.record && c.session_root.empty()) {
        throw common::Error(StatusCode::kInvalidArgument,
                            "session.record is true but session.root is empty");
    }
}

std::string PrintConfig(const RigConfig& config) {
    RigConfig copy = config;
    std::vector<Binding> bindings = Bindings(copy);
    std::ostringstream out;
    out << "# bimslam-rig effective configuration" << (config.handheld ? " (--handheld)" : "")
        << "\n";
    std::vector<std::string> open;  // the sections printed so far on the current path
    for (const Binding& b : bindings) {
        std::vector<std::string> parts;
        std::stringstream ss(b.key.path);
        for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
        size_t common = 0;
        while (common < open.size() && common + 1 < parts.size() && open[common] == parts[common])
            ++common;
        open.resize(common);
        for (size_t i = common; i + 1 < parts.size(); ++i) {
            out << std::string(2 * i, ' ') << parts[i] << ":\n";
            open.push_back(parts[i]);
        }
        const size_t depth = parts.size() - 1;
        out << std::string(2 * depth, ' ') << parts.back() << ": " << b.print() << "  # "
            << b.key.doc << "; " << b.key.type << " " << b.key.range
            << (b.key.unit.empty() ? "" : ", " + b.key.unit) << "\n";
    }
    return out.str();
}

}  // namespace bimslam::rig
