// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/simulate/simulate.hpp"

#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/common/utc_time.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/trajectory.hpp"
#include "algorithms/simulation/body_trajectory.hpp"
#include "algorithms/simulation/imu_model.hpp"
#include "algorithms/simulation/lidar_simulator.hpp"
#include "drivers/can/candump.hpp"
#include "drivers/can/go1_encoder.hpp"
#include "drivers/go1/high_state.hpp"
#include "drivers/net/can_pcap.hpp"
#include "drivers/ouster/metadata.hpp"
#include "host_tools/bim/lidar_from_metadata.hpp"
#include "host_tools/simulate/beam_hits.hpp"
#include "host_tools/simulate/building_walk.hpp"
#include "host_tools/simulate/go1_odometry.hpp"
#include "host_tools/simulate/ouster_writer.hpp"
#include "host_tools/simulate/rig_body.hpp"
#include "host_tools/simulate/scenario_yaml.hpp"
#include "host_tools/simulate/walk.hpp"
#include "host_tools/simulate/world.hpp"

namespace bimslam::simulate {
namespace {
using nlohmann::json;
constexpr double kImuRateHz = 100.0;        // Ouster IMU packets (LEGACY)
constexpr int64_t kCanTickNs = 5'000'000;   // the bridge's timer (drivers/can/go1_encoder.hpp)
constexpr int64_t kCanLatencyNs = 800'000;  // HighState receive to CAN transmit (SampleAge)

int64_t Ns(double t) { return int64_t(std::llround(t * 1e9)); }

json Vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

Eigen::Isometry3d MountTransform(const SensorSpec& s) {
    return common::PoseFromXyzRpyDeg(s.mount_xyz, s.mount_rpy_deg);
}

simulation::PathTiming TimingFor(const Scenario& s) {
    simulation::PathTiming timing;
    timing.speed_mps = s.speed.speed_mps;
    timing.max_accel_mps2 = s.speed.max_accel_mps2;
    timing.max_yaw_rate_radps = s.speed.max_yaw_rate_deg_s * kDeg;
    timing.max_lateral_accel_mps2 = s.speed.max_lateral_accel_mps2;
    timing.start_at_speed = s.speed.start_at_speed;
    return timing;
}

// The trajectory, its walk repeated until it lasts `duration_s` (0: once).
simulation::BodyTrajectory MakeTrajectory(const Walk& walk, const Scenario& s, size_t* laps) {
    const simulation::PathTiming timing = TimingFor(s);
    *laps = 1;
    for (;;) {
        simulation::BodyTrajectory t(RepeatWalk(walk, *laps), walk.start_yaw, walk.floor_z, timing,
                                     GaitFor(s.platform), s.seed);
        if (t.duration_s() >= s.duration_s) return t;
        *laps =
            std::max(*laps + 1, size_t(std::ceil(s.duration_s / t.duration_s() * double(*laps))));
    }
}

// A whole building's trajectory (storey: all), its walk repeated as MakeTrajectory does.
simulation::BodyTrajectory MakeBuildingTrajectory(const BuildingWalk& walk, const Scenario& s,
                                                  size_t* laps) {
    const simulation::PathTiming timing = TimingFor(s);
    *laps = 1;
    for (;;) {
        simulation::BodyTrajectory t(RepeatBuildingWalk(walk, *laps, /*closed=*/true),
                                     walk.start_yaw, timing, GaitFor(s.platform), s.seed);
        if (t.duration_s() >= s.duration_s) return t;
        *laps =
            std::max(*laps + 1, size_t(std::ceil(s.duration_s / t.duration_s() * double(*laps))));
    }
}

// The motion of the capture: one storey's walk (PlanWalk), or the whole building's
// (PlanBuildingWalk, storey: all), and what the capture's files say about it.
struct Motion {
    std::optional<simulation::BodyTrajectory> trajectory;
    int storey = 0;  // the storey walked, or where a building walk starts
    bool all_storeys = false;
    size_t laps = 1, waypoints = 0, flights_walked = 0;
    bool starts_outside = false;
    std::vector<std::string> notes;
    bim::OccupancyGrid grid;              // of `storey`, for clutter
    std::vector<Eigen::Vector2d> points;  // the walk on `storey`, which clutter keeps clear of
    std::vector<int> storeys;             // walked, in order
    std::vector<std::string> unreached;   // floors the stairs do not reach
};

Motion PlanMotion(const Scenario& s, const bim::BimModel& model) {
    Motion m;
    m.all_storeys = s.storey == kAllStoreys;
    if (!m.all_storeys && !s.path.waypoint_storeys.empty()) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "path.waypoint_storeys: only with storey: all (a walk of one storey "
                            "has its waypoints on it)");
    }
    if (!m.all_storeys) {
        m.storey =
            s.storey.empty() ? bim::DefaultWalkStorey(model) : bim::FindStorey(model, s.storey);
        Walk walk = PlanWalk(model, m.storey, s);
        m.trajectory.emplace(MakeTrajectory(walk, s, &m.laps));
        m.waypoints = walk.waypoints;
        m.starts_outside = walk.starts_outside;
        m.notes = walk.notes;
        m.grid = std::move(walk.grid);
        m.points = std::move(walk.points);
        if (!model.storeys.empty()) m.storeys = {m.storey};
        return m;
    }
    BuildingWalk walk = PlanBuildingWalk(model, s);
    m.trajectory.emplace(MakeBuildingTrajectory(walk, s, &m.laps));
    m.storey = walk.graph.start;
    m.waypoints = walk.waypoints;
    m.flights_walked = walk.flights_walked;
    m.starts_outside = walk.starts_outside;
    m.notes = walk.notes;
    m.grid = walk.graph.grids[size_t(m.storey)];
    for (const simulation::PathPoint& p : walk.points) {
        if (std::abs(p.p.z() - m.grid.floor_z) < 1e-6) m.points.push_back(p.p.head<2>());
    }
    m.storeys = walk.storeys;
    for (const int f : walk.graph.floors) {
        if (!walk.graph.Reaches(f)) m.unreached.push_back(model.storeys[size_t(f)].name);
    }
    return m;
}

simulation::NoiseModel LidarNoise(const LidarNoiseSpec& spec, const ouster::SensorInfo& info) {
    simulation::NoiseModel n;
    n.range_sigma_m = spec.range_sigma_m;
    n.dropout_base = spec.dropout;
    n.max_range_m = spec.max_range_m;
    n.glass_return_probability = spec.glass_return_probability;
    n.glass_return_exponent = spec.glass_return_exponent;
    // The RNG15 profiles carry ranges in 8 mm steps (specs/ouster-lidar.md).
    const ouster::LidarProfile p = info.format.lidar_profile;
    const bool rng15 = p == ouster::LidarProfile::kRng15Rfl8Nir8 ||
                       p == ouster::LidarProfile::kRng15Rfl8Nir8Dual ||
                       p == ouster::LidarProfile::kFusaRng15Rfl8Nir8Dual;
    n.range_resolution_mm = rng15 ? 8 : 1;
    return n;
}

// The UDP stream the Go1 itself sends the bridge: a HighState every 2 ms (500 Hz, what the
// SDK's examples poll at) from 192.168.123.161:8082 to the bridge at 192.168.123.200:8090, each
// carrying the model's latest 10 ms sample (the same samples, from a model with the same seed,
// as the CAN log the bridge would make of it), stamped by the capturing host's clock. Running
// the real bimslam-go1-bridge on it exercises its HighState-to-CAN mapping end to end.
void WriteHighStates(const simulation::BodyTrajectory& trajectory, const Scenario& s,
                     const simulation::ImuNoise& imu_noise, double end_s,
                     const std::filesystem::path& dir) {
    Go1OdometryModel model(trajectory, s.noise.odometry, imu_noise, s.seed);
    net::PcapWriter pcap(dir / "go1_highstate.pcap");
    std::array<uint8_t, go1::kHighStateSize> bytes{};
    go1::HighState h;
    h.head = {0xFE, 0xEF};
    h.level_flag = go1::kHighLevel;
    const uint32_t go1_ip = 0xC0A87BA1, bridge_ip = 0xC0A87BC8;  // .161 and .200
    for (int64_t t_ns = 0; t_ns <= Ns(end_s); t_ns += 10'000'000) {
        const can::Go1Sample g = model.Next(double(t_ns) * 1e-9);
        for (int i = 0; i < 4; ++i) h.imu.quaternion[size_t(i)] = float(g.quat_wxyz[size_t(i)]);
        for (size_t i = 0; i < 3; ++i) {
            h.imu.gyroscope[i] = float(g.gyro[i]);
            h.imu.accelerometer[i] = float(g.accel[i]);
        }
        const Eigen::Quaterniond q(g.quat_wxyz[0], g.quat_wxyz[1], g.quat_wxyz[2], g.quat_wxyz[3]);
        const Eigen::Vector3d rpy = q.toRotationMatrix().eulerAngles(2, 1, 0);
        h.imu.rpy = {float(rpy[2]), float(rpy[1]), float(g.odom_yaw)};
        h.imu.temperature = g.imu_temperature_c;
        for (size_t leg = 0; leg < 4; ++leg) h.foot_force[leg] = int16_t(g.foot_force_raw[leg]);
        h.bms.soc = g.battery_soc;
        h.mode = g.mode;
        h.gait_type = g.gait;
        h.foot_raise_height = float(g.foot_raise_height);
        h.position = {float(g.odom_x), float(g.odom_y), float(g.odom_z)};
        h.body_height = float(g.body_height);
        h.velocity = {float(g.vx), float(g.vy), float(g.vz)};  // [2]: rotateSpeed (comm.h)
        h.yaw_speed = float(g.yaw_rate);
        go1::SerializeHighState(h, bytes, s.network.go1_highstate_crc);
        const int64_t host0 = kSensorBootNs + HostMinusSensorNs(s) + t_ns;
        for (int64_t k = 0; k < 5; ++k) {
            pcap.WriteUdp(host0 + k * 2'000'000, go1_ip, 8082, bridge_ip, 8090, bytes);
        }
    }
    pcap.Close();
}

// The Go1 bridge's CAN traffic over the whole capture.
uint64_t WriteCan(const simulation::BodyTrajectory& trajectory, const Scenario& s,
                  const simulation::ImuNoise& imu_noise, double end_s,
                  const std::filesystem::path& dir, json* manifest) {
    Go1OdometryModel model(trajectory, s.noise.odometry, imu_noise, s.seed);
    can::Go1EncoderConfig config;
    config.frame_spacing_ns = 230'000;  // an 8-byte frame at 500 kbit/s
    can::Go1Encoder encoder(config);
    can::CandumpWriter log(dir / "go1_can.log");
    net::PcapWriterConfig pc;
    pc.link_type = net::kLinkTypeCanSocketcan;
    net::PcapWriter pcap(dir / "go1_can.pcap", pc);
    std::array<common::CanFrame, can::Go1Encoder::kMaxFramesPerTick> frames;
    can::Go1Sample sample;
    uint64_t written = 0;
    for (int64_t tick = 0; tick * kCanTickNs <= Ns(end_s); ++tick) {
        const double t = double(tick * kCanTickNs) * 1e-9;
        if (encoder.sample_tick_next()) {
            sample = model.Next(t);
            sample.bridge_time_ns = kBridgeBootNs + tick * kCanTickNs;
        }
        const int64_t host =
            kSensorBootNs + HostMinusSensorNs(s) + tick * kCanTickNs + kCanLatencyNs;
        const size_t n = encoder.Tick(&sample, host, frames);
        for (size_t i = 0; i < n; ++i) {
            log.Write(frames[i], "can0");
            net::WriteCanFrame(pcap, frames[i]);
        }
        written += n;
    }
    log.Close();
    pcap.Close();
    WriteHighStates(trajectory, s, imu_noise, end_s, dir);
    json slips = json::array();
    for (const SlipInterval& slip : model.slips()) {
        if (slip.begin_s < end_s) slips.push_back({slip.begin_s, slip.end_s});
    }
    (*manifest)["go1"] = {{"can_log", "go1_can.log"},
                          {"highstate_pcap", "go1_highstate.pcap"},
                          {"highstate_crc", go1::ToString(s.network.go1_highstate_crc)},
                          {"can_pcap", "go1_can.pcap"},
                          {"frames", written},
                          {"interface", "can0"},
                          {"scale_error", s.noise.odometry.scale_error},
                          {"yaw_drift_radps", model.yaw_drift_radps()},
                          {"slips_s", slips},
                          {"slip_factor", s.noise.odometry.slip_factor}};
    if (model.nosing_slips() > 0) (*manifest)["go1"]["nosing_slips"] = model.nosing_slips();
    return written;
}

}  // namespace

void ColumnPoses(const simulation::BodyTrajectory& trajectory,
                 const Eigen::Isometry3d& T_base_sensor, const simulation::LidarModel& lidar,
                 double t0, std::span<Eigen::Isometry3d> poses) {
    for (int v = 0; v < lidar.columns && size_t(v) < poses.size(); ++v) {
        const double t = t0 + double(lidar.ColumnTimeOffsetNs(v)) * 1e-9;
        poses[size_t(v)] = trajectory.Pose(t) * T_base_sensor;
    }
}

namespace {

// What the report says of the motion; the captured length is the planar path every 0.1 s up to
// the capture's end (a --duration shorter than the walk covers part of it).
void DescribeMotion(const Motion& motion, const bim::BimModel& model, double end_s,
                    CaptureReport* r) {
    const simulation::BodyTrajectory& trajectory = *motion.trajectory;
    r->laps = motion.laps;
    r->walk_length_m = trajectory.length_m();
    Eigen::Vector2d last = trajectory.PlanarAt(0).xy;
    for (int k = 1; k <= int(std::ceil(end_s / 0.1)); ++k) {
        const Eigen::Vector2d xy = trajectory.PlanarAt(std::min(0.1 * k, end_s)).xy;
        r->captured_length_m += (xy - last).norm();
        last = xy;
    }
    r->starts_outside = motion.starts_outside;
    r->notes = motion.notes;
    if (!model.storeys.empty()) r->storey = model.storeys[size_t(motion.storey)].name;
    for (const int k : motion.storeys) r->storeys.push_back(model.storeys[size_t(k)].name);
    r->flights_walked = motion.flights_walked;
    r->unreached_storeys = motion.unreached;
}

simulation::ImuNoise ImuNoiseFor(const Scenario& s) {
    simulation::ImuNoise imu_noise;
    imu_noise.accel_sigma_mps2 = s.noise.imu.accel_sigma_mps2;
    imu_noise.gyro_sigma_radps = s.noise.imu.gyro_sigma_deg_s * kDeg;
    imu_noise.accel_bias_sigma_mps2 = s.noise.imu.accel_bias_sigma_mps2;
    imu_noise.gyro_bias_sigma_radps = s.noise.imu.gyro_bias_sigma_deg_s * kDeg;
    return imu_noise;
}

// The lidar frames and IMU packets of the walk into `writer`; returns the ground truth (the
// sensor's pose at column 0 of each frame). `hits` counts the beams on what the scenario changed.
std::vector<io::StampedPose> CastFrames(const simulation::BodyTrajectory& trajectory,
                                        const World& world, const Scenario& s,
                                        const ouster::SensorInfo& info,
                                        const simulation::ImuModel& imu, size_t frames,
                                        double end_s, OusterWriter& writer, BeamHitCounter& hits,
                                        const std::function<void(double)>& progress) {
    const simulation::Scene scene(world.mesh, world.ids, world.materials);
    const simulation::LidarModel lidar = bim::LidarModelFromSensorInfo(info);
    const simulation::NoiseModel noise = LidarNoise(s.noise.lidar, info);
    const Eigen::Isometry3d T_base_sensor = MountTransform(s.sensor);
    // The platform's body, fixed in the sensor frame (rig_body.hpp).
    common::TriangleMesh body = RigBody(s.platform);
    const Eigen::Isometry3d T_sensor_base = T_base_sensor.inverse();
    for (Eigen::Vector3f& p : body.vertices) p = (T_sensor_base * p.cast<double>()).cast<float>();
    const simulation::Scene rig(body, std::vector<uint32_t>(body.triangles.size(), kRigId));
    // IMU samples are expressed in the sensor frame at the IMU's position (the encoder rotates
    // them into the IMU's frame, drivers/ouster/packet_encoder.hpp).
    Eigen::Isometry3d T_base_imu = T_base_sensor;
    T_base_imu.translate(Eigen::Vector3d(info.imu_to_sensor_transform.block<3, 1>(0, 3) * 1e-3));

    const int w = lidar.columns;
    const double period_s = 1.0 / lidar.frame_rate_hz;
    std::vector<io::StampedPose> truth;
    std::vector<uint64_t> column_ns(static_cast<size_t>(w));
    std::vector<ouster::ImuSample> imu_batch;
    uint64_t imu_index = 0;
    auto take_imu_until = [&](double until_s) {
        imu_batch.clear();
        for (; double(imu_index) / kImuRateHz <= until_s; ++imu_index) {
            const double t = double(imu_index) / kImuRateHz;
            const auto k = trajectory.KinematicsAt(t, T_base_imu);
            const simulation::ImuMeasurement m =
                imu.Measure(imu_index, k.specific_force_frame, k.omega_frame);
            ouster::ImuSample sample;
            sample.time_ns = sample.gyro_time_ns = uint64_t(kSensorBootNs + Ns(t));
            sample.accel = m.accel;
            sample.gyro = m.gyro;
            imu_batch.push_back(sample);
        }
    };
    simulation::ScanImage image;
    std::vector<Eigen::Isometry3d> poses(static_cast<size_t>(w));
    std::vector<uint32_t> overlay_ids;
    for (size_t k = 0; k < frames; ++k) {
        const double t0 = double(k) * period_s;
        ColumnPoses(trajectory, T_base_sensor, lidar, t0, poses);
        for (int v = 0; v < w; ++v) {
            column_ns[size_t(v)] = uint64_t(kSensorBootNs + Ns(t0) + lidar.ColumnTimeOffsetNs(v));
        }
        // People and doors move between scans, not within one (at 1.2 m/s, 12 cm a scan; a door
        // swinging 90 degrees in 4 s, 2.3 degrees). A door the sensor is near stands open.
        common::TriangleMesh moving =
            PeopleMesh(world.people, world.people_floor_z, t0 + 0.5 * period_s, &overlay_ids);
        AppendDoorLeaves(world.doors, t0 + 0.5 * period_s,
                         poses[size_t(w / 2)].translation().head<2>(), &moving, &overlay_ids);
        const simulation::Scene overlay(moving, overlay_ids);
        simulation::SimulatorOptions options;
        options.overlay = moving.triangles.empty() ? nullptr : &overlay;
        options.rig = s.sensor.body_in_view ? &rig : nullptr;
        simulation::SimulateScan(scene, lidar, std::span<const Eigen::Isometry3d>(poses), noise,
                                 s.seed ^ (uint64_t(k) * 0x9E3779B97F4A7C15ull), &image, options);
        hits.Count(lidar, poses, image);
        take_imu_until(t0 + period_s - 1e-9);
        writer.WriteFrame(uint32_t(k), image, column_ns, imu_batch);
        truth.push_back(io::StampedPose::FromIsometry(int64_t(column_ns[0]), poses[0]));
        if (progress && (k % 10 == 0 || k + 1 == frames)) progress(double(k + 1) / double(frames));
    }
    take_imu_until(end_s);
    writer.WriteImu(imu_batch);
    return truth;
}

// capture.json (the Go1's part already in `manifest`, from WriteCan).
void WriteManifest(const Scenario& s, const bim::BimModel& model, const std::string& model_sha256,
                   const ouster::SensorInfo& info, const simulation::ImuModel& imu,
                   const simulation::ImuNoise& imu_noise, const Motion& motion,
                   const CaptureReport& r, const std::filesystem::path& dir, json manifest) {
    std::vector<double> mount(16);
    Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(mount.data()) =
        MountTransform(s.sensor).matrix();
    manifest["format"] = "bimslam-capture";
    manifest["version"] = 1;
    manifest["model"] = {{"file", model.file}, {"sha256", model_sha256}, {"storey", r.storey}};
    manifest["platform"] = ToString(s.platform);
    // When the walk started (the host clock at t = 0): `bimslam map` dates its visits by it.
    manifest["start"] = common::FormatUtcTime(CaptureStartNs(s));
    manifest["start_ns"] = CaptureStartNs(s);
    manifest["files"] = {{"lidar_pcap", "lidar.pcap"},
                         {"metadata", "metadata.json"},
                         {"ground_truth", "ground_truth.tum"},
                         {"changes", "changes.json"},
                         {"scenario", "scenario.yaml"}};
    if (s.platform == Platform::kGo1) {
        manifest["files"]["go1_can_log"] = "go1_can.log";
        manifest["files"]["go1_can_pcap"] = "go1_can.pcap";
    }
    manifest["ground_truth"] = "T_bim_sensor at column 0 of each lidar frame, sensor clock";
    manifest["clocks"] = {{"sensor_ns_at_start", kSensorBootNs},
                          {"host_minus_sensor_ns", HostMinusSensorNs(s)},
                          {"bridge_ns_at_start", kBridgeBootNs}};
    manifest["sensor"] = {{"lidar_mode", info.lidar_mode},
                          {"udp_profile_lidar", ouster::ToString(info.format.lidar_profile)},
                          {"prod_sn", info.prod_sn},
                          {"init_id", info.init_id},
                          {"udp_port_lidar", info.udp_port_lidar.value_or(7502)},
                          {"udp_port_imu", info.udp_port_imu.value_or(7503)},
                          {"T_base_sensor", mount}};
    manifest["imu"] = {{"rate_hz", kImuRateHz},
                       {"frame", "sensor"},
                       {"accel_bias_mps2", Vec(imu.accel_bias())},
                       {"gyro_bias_radps", Vec(imu.gyro_bias())},
                       {"accel_sigma_mps2", imu_noise.accel_sigma_mps2},
                       {"gyro_sigma_radps", imu_noise.gyro_sigma_radps}};
    manifest["walk"] = {{"duration_s", r.duration_s},
                        {"length_m", r.walk_length_m},
                        {"laps", r.laps},
                        {"starts_outside", r.starts_outside},
                        {"waypoints", motion.waypoints}};
    if (motion.all_storeys) {
        manifest["files"]["ground_truth_storeys"] = "ground_truth_storeys.csv";
        manifest["model"]["storey"] = kAllStoreys;
        manifest["model"]["start_storey"] = r.storey;
        manifest["walk"]["storeys"] = r.storeys;
        manifest["walk"]["flights_walked"] = r.flights_walked;
        manifest["walk"]["notes"] = r.notes;
    }
    manifest["packets"] = {{"frames", r.frames},
                           {"lidar", r.lidar_packets},
                           {"imu", r.imu_packets},
                           {"lost", r.lost_packets},
                           {"fragmented", s.network.fragment}};
    io::WriteFileAtomic(dir / "capture.json", manifest.dump(2) + "\n");
}

}  // namespace

int64_t CaptureStartNs(const Scenario& s) {
    return s.date.empty() ? kDefaultStartNs : common::ParseUtcTime(s.date);
}

CaptureReport SimulateCapture(const Scenario& s, const bim::BimModel& model,
                              const std::string& model_sha256, const std::filesystem::path& dir,
                              const std::function<void(double)>& progress, const HitWatch& watch) {
    const auto wall_start = std::chrono::steady_clock::now();
    s.Validate();
    if (!model.origin_m.isZero()) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            model.file +
                                ": the geometry lies more than 10 km from the model's "
                                "origin; the simulator needs it near the origin");
    }
    // The walk and its motion, the world as built, the sensor.
    const Motion motion = PlanMotion(s, model);
    const simulation::BodyTrajectory& trajectory = *motion.trajectory;
    const double end_s = s.duration_s > 0 ? s.duration_s : trajectory.duration_s();
    CaptureReport r;
    r.dir = dir;
    DescribeMotion(motion, model, end_s, &r);
    const World world =
        BuildWorld(model, motion.storey, s.edits, motion.grid, motion.points, s.seed);
    const ouster::SensorInfo info = SensorFor(s.sensor);
    const simulation::ImuNoise imu_noise = ImuNoiseFor(s);
    const simulation::ImuModel imu(imu_noise, s.seed ^ 0x1A0ull);

    // The lidar and its IMU, the ground truth.
    std::filesystem::create_directories(dir);
    io::WriteFileAtomic(dir / "metadata.json", ouster::SerializeMetadata(info));
    net::PcapWriter pcap(dir / "lidar.pcap");
    OusterWriter writer(info, pcap, s.network, s.seed, HostMinusSensorNs(s),
                        kSensorBootNs + Ns(s.sensor.clock_jump_at_s), Ns(s.sensor.clock_jump_s));
    const double period_s = 1.0 / double(bim::LidarModelFromSensorInfo(info).frame_rate_hz);
    const size_t frames = size_t(std::floor(end_s / period_s + 1e-9));
    BeamHitCounter hits(model, world, watch);
    const std::vector<io::StampedPose> truth =
        CastFrames(trajectory, world, s, info, imu, frames, end_s, writer, hits, progress);
    pcap.Close();
    io::WriteTum(dir / "ground_truth.tum", truth);
    if (motion.all_storeys) WriteStoreyTruth(trajectory, model, truth, dir);

    // The Go1's CAN, the edits' truth, the scenario as run, the manifest.
    json manifest;
    if (s.platform == Platform::kGo1) {
        r.can_frames = WriteCan(trajectory, s, imu_noise, end_s, dir, &manifest);
    }
    json changes = WriteChanges(world, dir);
    hits.AddTo(changes);
    if (motion.all_storeys) AddStoreys(model, changes);
    io::WriteFileAtomic(dir / "changes.json", changes.dump(2) + "\n");
    io::WriteFileAtomic(dir / "scenario.yaml", ScenarioToYaml(s));

    r.duration_s = end_s;
    r.frames = frames;
    r.lidar_packets = writer.stats().lidar_packets;
    r.imu_packets = writer.stats().imu_packets;
    r.lost_packets = writer.stats().lost_packets;
    r.pcap_bytes = std::filesystem::file_size(dir / "lidar.pcap");
    r.added_objects = changes["added"].size();
    r.removed_elements = changes["removed"].size();
    r.moved_elements = changes["moved"].size();
    r.people = world.people.size();
    r.watched_hits = hits.Watched();
    WriteManifest(s, model, model_sha256, info, imu, imu_noise, motion, r, dir,
                  std::move(manifest));
    r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    return r;
}

}  // namespace bimslam::simulate
