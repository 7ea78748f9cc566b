// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Round trip of every bimslam LCM message: over UDP multicast (lcm::LCM udpm://) and through an
// LCM log file (published with lcm::LCM file://...?mode=w, read back with lcm::LogFile). Every
// field is filled with a distinct value and compared explicitly, and the encoded bytes must match.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <bimslam/bim_pose_t.hpp>
#include <bimslam/can_frame_t.hpp>
#include <bimslam/go1_bridge_status_t.hpp>
#include <bimslam/go1_state_t.hpp>
#include <bimslam/imu_sample_t.hpp>
#include <bimslam/keyframe_t.hpp>
#include <bimslam/odometry_t.hpp>
#include <bimslam/ouster_stats_t.hpp>
#include <bimslam/rig_health_t.hpp>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "tests/support/test_support.hpp"

namespace bimslam::lcmtypes {
namespace {
namespace BIMSLAM_UNITY_ID {

using Bytes = std::vector<uint8_t>;

constexpr char kUdpmUrl[] = "udpm://239.255.76.67:7667?ttl=0";
// Above ~200 kB a message overflows the default socket receive buffer (rmem_default 212992 B).
constexpr char kUdpmBigUrl[] = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";
constexpr int kBigKeyframePoints = 20000;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A channel name no other process (parallel ctest runs) uses.
std::string UniqueChannel(const std::string& what) {
    static std::atomic<int> counter{0};
    return "BIMSLAM_LCM_TEST_" + std::to_string(::getpid()) + "_" + what + "_" +
           std::to_string(counter++);
}

template <class T>
Bytes Encode(const T& msg) {
    Bytes bytes(static_cast<size_t>(msg.getEncodedSize()));
    const int n = msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    EXPECT_EQ(n, static_cast<int>(bytes.size()));
    return bytes;
}

// ------------------------------------------------------------------------------------------------
// Field comparison: integers and strings exactly, floating point exactly or both NaN (NaN is the
// documented invalid value), arrays element by element.

template <class T>
void ExpectSame(const T& a, const T& b, const std::string& name) {
    if constexpr (std::is_floating_point_v<T>) {
        if (std::isnan(a) || std::isnan(b)) {
            EXPECT_TRUE(std::isnan(a) && std::isnan(b)) << name << ": " << a << " vs " << b;
        } else {
            EXPECT_EQ(a, b) << name;
        }
    } else {
        EXPECT_EQ(a, b) << name;
    }
}

template <class T, size_t N>
void ExpectSame(const T (&a)[N], const T (&b)[N], const std::string& name) {
    for (size_t i = 0; i < N; ++i) {
        ExpectSame(a[i], b[i], name + "[" + std::to_string(i) + "]");
    }
}

template <class T>
void ExpectSame(const std::vector<T>& a, const std::vector<T>& b, const std::string& name) {
    ASSERT_EQ(a.size(), b.size()) << name;
    for (size_t i = 0; i < a.size(); ++i) {
        ExpectSame(a[i], b[i], name + "[" + std::to_string(i) + "]");
    }
}

#define EXPECT_FIELD(field) ExpectSame(a.field, b.field, #field)

void ExpectSameMessage(const odometry_t& a, const odometry_t& b) {
    EXPECT_FIELD(schema_version);
    EXPECT_FIELD(sample_time_ns);
    EXPECT_FIELD(publish_time_ns);
    EXPECT_FIELD(scan_start_time_ns);
    EXPECT_FIELD(scan_end_time_ns);
    EXPECT_FIELD(scan_index);
    EXPECT_FIELD(status);
    EXPECT_FIELD(degenerate_directions);
    EXPECT_FIELD(position);
    EXPECT_FIELD(orientation_w);
    EXPECT_FIELD(orientation_x);
    EXPECT_FIELD(orientation_y);
    EXPECT_FIELD(orientation_z);
    EXPECT_FIELD(linear_velocity);
    EXPECT_FIELD(angular_velocity);
    EXPECT_FIELD(pose_covariance);
    EXPECT_FIELD(solve_time_ns);
    EXPECT_FIELD(iterations);
    EXPECT_FIELD(num_scan_points);
    EXPECT_FIELD(num_correspondences);
    EXPECT_FIELD(num_map_points);
    EXPECT_FIELD(residual_rms);
    EXPECT_FIELD(min_information_eigenvalue);
}

void ExpectSameMessage(const keyframe_t& a, const keyframe_t& b) {
    EXPECT_FIELD(schema_version);
    EXPECT_FIELD(sample_time_ns);
    EXPECT_FIELD(publish_time_ns);
    EXPECT_FIELD(keyframe_id);
    EXPECT_FIELD(scan_index);
    EXPECT_FIELD(position);
    EXPECT_FIELD(orientation_w);
    EXPECT_FIELD(orientation_x);
    EXPECT_FIELD(orientation_y);
    EXPECT_FIELD(orientation_z);
    EXPECT_FIELD(descriptor_kind);
    EXPECT_FIELD(num_rings);
    EXPECT_FIELD(num_sectors);
    EXPECT_FIELD(max_radius);
    EXPECT_FIELD(num_cells);
    EXPECT_FIELD(cells);
    EXPECT_FIELD(voxel_size);
    EXPECT_FIELD(num_points);
    EXPECT_FIELD(x);
    EXPECT_FIELD(y);
    EXPECT_FIELD(z);
    EXPECT_FIELD(intensity);
}

void ExpectSameMessage(const ouster_stats_t& a, const ouster_stats_t& b) {
    EXPECT_FIELD(schema_version);
    EXPECT_FIELD(sample_time_ns);
    EXPECT_FIELD(publish_time_ns);
    EXPECT_FIELD(counting_since_ns);
    EXPECT_FIELD(interval_start_time_ns);
    EXPECT_FIELD(prod_sn);
    EXPECT_FIELD(init_id);
    EXPECT_FIELD(lidar_packets_received);
    EXPECT_FIELD(lidar_packets_accepted);
    EXPECT_FIELD(imu_packets_received);
    EXPECT_FIELD(imu_packets_accepted);
    EXPECT_FIELD(bytes_received);
    EXPECT_FIELD(frames_complete);
    EXPECT_FIELD(frames_incomplete);
    EXPECT_FIELD(columns_lost);
    EXPECT_FIELD(packets_lost);
    EXPECT_FIELD(sensor_restarts);
    EXPECT_FIELD(rejected_wrong_size);
    EXPECT_FIELD(rejected_wrong_prod_sn);
    EXPECT_FIELD(rejected_wrong_init_id);
    EXPECT_FIELD(rejected_crc);
    EXPECT_FIELD(rejected_late);
    EXPECT_FIELD(rejected_unknown_port);
    EXPECT_FIELD(rejected_not_ouster);
    EXPECT_FIELD(crc_checked);
    EXPECT_FIELD(crc_failures);
    EXPECT_FIELD(latency_mean_ns);
    EXPECT_FIELD(latency_max_ns);
    EXPECT_FIELD(latency_frames);
}

void ExpectSameMessage(const go1_state_t& a, const go1_state_t& b) {
    EXPECT_FIELD(schema_version);
    EXPECT_FIELD(sample_time_ns);
    EXPECT_FIELD(publish_time_ns);
    EXPECT_FIELD(receive_time_ns);
    EXPECT_FIELD(alive_counter);
    EXPECT_FIELD(valid_groups);
    EXPECT_FIELD(fresh_groups);
    EXPECT_FIELD(timed_out_groups);
    EXPECT_FIELD(flags);
    EXPECT_FIELD(bridge_time_raw_us);
    EXPECT_FIELD(sample_age_us);
    EXPECT_FIELD(velocity_x);
    EXPECT_FIELD(velocity_y);
    EXPECT_FIELD(yaw_rate);
    EXPECT_FIELD(velocity_z);
    EXPECT_FIELD(body_height);
    EXPECT_FIELD(foot_raise_height);
    EXPECT_FIELD(gyro);
    EXPECT_FIELD(accel);
    EXPECT_FIELD(orientation_w);
    EXPECT_FIELD(orientation_x);
    EXPECT_FIELD(orientation_y);
    EXPECT_FIELD(orientation_z);
    EXPECT_FIELD(foot_contact);
    EXPECT_FIELD(foot_force_raw);
    EXPECT_FIELD(odom_position);
    EXPECT_FIELD(odom_yaw);
    EXPECT_FIELD(mode);
    EXPECT_FIELD(gait);
    EXPECT_FIELD(battery_soc_percent);
    EXPECT_FIELD(imu_temperature_degc);
    EXPECT_FIELD(udp_rx_lost);
    EXPECT_FIELD(bridge_state);
    EXPECT_FIELD(frames_received);
    EXPECT_FIELD(frames_unknown_id);
    EXPECT_FIELD(e2e_crc_errors);
    EXPECT_FIELD(e2e_counter_lost);
    EXPECT_FIELD(e2e_counter_repeats);
    EXPECT_FIELD(e2e_counter_resyncs);
    EXPECT_FIELD(e2e_timeouts);
}

void ExpectSameMessage(const imu_sample_t& a, const imu_sample_t& b) {
    EXPECT_FIELD(schema_version);
    EXPECT_FIELD(sample_time_ns);
    EXPECT_FIELD(publish_time_ns);
    EXPECT_FIELD(accel_time_offset_ns);
    EXPECT_FIELD(source);
    EXPECT_FIELD(sequence);
    EXPECT_FIELD(flags);
    EXPECT_FIELD(angular_velocity);
    EXPECT_FIELD(linear_acceleration);
    EXPECT_FIELD(orientation_w);
    EXPECT_FIELD(orientation_x);
    EXPECT_FIELD(orientation_y);
    EXPECT_FIELD(orientation_z);
}

void ExpectSameMessage(const rig_health_t& a, const rig_health_t& b) {
    EXPECT_FIELD(schema_version);
    EXPECT_FIELD(sample_time_ns);
    EXPECT_FIELD(publish_time_ns);
    EXPECT_FIELD(interval_start_time_ns);
    EXPECT_FIELD(uptime_ns);
    EXPECT_FIELD(faults);
    EXPECT_FIELD(faults_latched);
    EXPECT_FIELD(num_fault_counts);
    EXPECT_FIELD(fault_counts);
    EXPECT_FIELD(num_threads);
    EXPECT_FIELD(thread_name);
    EXPECT_FIELD(thread_cycles);
    EXPECT_FIELD(thread_deadline_misses);
    EXPECT_FIELD(thread_deadline_ns);
    EXPECT_FIELD(thread_max_cycle_ns);
    EXPECT_FIELD(thread_cpu_percent);
    EXPECT_FIELD(thread_stalls);
    EXPECT_FIELD(num_queues);
    EXPECT_FIELD(queue_name);
    EXPECT_FIELD(queue_depth);
    EXPECT_FIELD(queue_max_depth);
    EXPECT_FIELD(queue_capacity);
    EXPECT_FIELD(queue_drops);
    EXPECT_FIELD(process_cpu_percent);
    EXPECT_FIELD(process_rss_bytes);
    EXPECT_FIELD(disk_free_bytes);
    EXPECT_FIELD(session_bytes_written);
    EXPECT_FIELD(session_dir);
}

void ExpectSameMessage(const can_frame_t& a, const can_frame_t& b) {
    EXPECT_FIELD(schema_version);
    EXPECT_FIELD(sample_time_ns);
    EXPECT_FIELD(publish_time_ns);
    EXPECT_FIELD(id);
    EXPECT_FIELD(flags);
    EXPECT_FIELD(len);
    EXPECT_FIELD(data);
}

void ExpectSameMessage(const bim_pose_t& a, const bim_pose_t& b) {
    EXPECT_FIELD(schema_version);
    EXPECT_FIELD(sample_time_ns);
    EXPECT_FIELD(publish_time_ns);
    EXPECT_FIELD(keyframe_time_ns);
    EXPECT_FIELD(state);
    EXPECT_FIELD(consistent_loops);
    EXPECT_FIELD(num_hypotheses);
    EXPECT_FIELD(position);
    EXPECT_FIELD(orientation);
    EXPECT_FIELD(pose_covariance);
    EXPECT_FIELD(storey);
    EXPECT_FIELD(space_name);
    EXPECT_FIELD(space_global_id);
}

void ExpectSameMessage(const go1_bridge_status_t& a, const go1_bridge_status_t& b) {
    EXPECT_FIELD(schema_version);
    EXPECT_FIELD(sample_time_ns);
    EXPECT_FIELD(publish_time_ns);
    EXPECT_FIELD(uptime_ns);
    EXPECT_FIELD(sequence);
    EXPECT_FIELD(state);
    EXPECT_FIELD(udp_link_ok);
    EXPECT_FIELD(crc_check);
    EXPECT_FIELD(crc_forms_seen);
    EXPECT_FIELD(polls);
    EXPECT_FIELD(datagrams);
    EXPECT_FIELD(highstates_crc_plain);
    EXPECT_FIELD(highstates_crc_scrambled);
    EXPECT_FIELD(rejected_size);
    EXPECT_FIELD(rejected_head);
    EXPECT_FIELD(rejected_level_flag);
    EXPECT_FIELD(rejected_crc);
    EXPECT_FIELD(lost);
    EXPECT_FIELD(link_losses);
    EXPECT_FIELD(can_samples);
    EXPECT_FIELD(can_frames);
    EXPECT_FIELD(can_send_failures);
    EXPECT_FIELD(udp_errors);
}

#undef EXPECT_FIELD

// ------------------------------------------------------------------------------------------------
// Messages with every field set to a distinct, non-default value. Values come from a sequence so
// that two fields never hold the same value (a swapped field would go unnoticed otherwise); int64
// values use the high bytes too, floating-point values are not integers.

class Values {
public:
    int64_t I64() { return 1'000'000'000'007 * Next() + 0x0102030405; }
    int32_t I32() { return static_cast<int32_t>(100'003 * Next()); }
    int16_t I16() { return static_cast<int16_t>(10 + Next()); }
    double F64() { return 0.123456789012345 + 1.5 * static_cast<double>(Next()); }
    float F32() { return 0.25f + 0.75f * static_cast<float>(Next()); }
    std::string Str(const std::string& prefix) { return prefix + "_" + std::to_string(Next()); }

    template <class T, size_t N>
    void Fill(T (&array)[N]) {
        for (T& v : array) {
            if constexpr (std::is_same_v<T, double>) {
                v = F64();
            } else if constexpr (std::is_same_v<T, float>) {
                v = F32();
            } else if constexpr (std::is_same_v<T, int64_t>) {
                v = I64();
            } else if constexpr (std::is_same_v<T, int16_t>) {
                v = I16();
            } else {
                v = static_cast<T>(I32());
            }
        }
    }

private:
    int64_t Next() { return ++k_; }
    int64_t k_ = 0;
};

// ORs int32 bit constants. lcm-gen's default C++ output makes every int32_t constant its own
// unnamed enum, and C++20 deprecates `|` between two different enums
// (-Wdeprecated-enum-enum-conversion); with --cpp-std=c++11 they are static constexpr int32_t and
// this still works.
template <class... Bit>
constexpr int32_t Bits(Bit... bits) {
    return (0 | ... | static_cast<int32_t>(bits));
}

odometry_t MakeOdometry() {
    Values v;
    odometry_t m;
    m.schema_version = odometry_t::SCHEMA_VERSION;
    m.sample_time_ns = v.I64();
    m.publish_time_ns = v.I64();
    m.scan_start_time_ns = v.I64();
    m.scan_end_time_ns = v.I64();
    m.scan_index = v.I64();
    m.status = Bits(odometry_t::STATUS_VALID, odometry_t::STATUS_DEGENERATE,
                    odometry_t::STATUS_PRIOR_USED_IMU, odometry_t::STATUS_DESKEWED);
    m.degenerate_directions = Bits(odometry_t::DEGENERATE_X, odometry_t::DEGENERATE_YAW);
    v.Fill(m.position);
    m.orientation_w = 0.5;
    m.orientation_x = -0.5;
    m.orientation_y = 0.5;
    m.orientation_z = -0.5;
    v.Fill(m.linear_velocity);
    v.Fill(m.angular_velocity);
    v.Fill(m.pose_covariance);
    m.solve_time_ns = v.I64();
    m.iterations = v.I32();
    m.num_scan_points = v.I32();
    m.num_correspondences = v.I32();
    m.num_map_points = v.I32();
    m.residual_rms = v.F32();
    m.min_information_eigenvalue = v.F32();
    return m;
}

keyframe_t MakeKeyframe(int num_points) {
    Values v;
    keyframe_t m;
    m.schema_version = keyframe_t::SCHEMA_VERSION;
    m.sample_time_ns = v.I64();
    m.publish_time_ns = v.I64();
    m.keyframe_id = v.I64();
    m.scan_index = v.I64();
    v.Fill(m.position);
    m.orientation_w = 0.9238795325112867;
    m.orientation_x = 0.0;
    m.orientation_y = 0.0;
    m.orientation_z = 0.3826834323650898;
    m.descriptor_kind = keyframe_t::DESCRIPTOR_SCAN_CONTEXT;
    m.num_rings = 20;
    m.num_sectors = 60;
    m.max_radius = 80.0f;
    m.num_cells = m.num_rings * m.num_sectors;
    for (int i = 0; i < m.num_cells; ++i) {
        m.cells.push_back(v.F32());
    }
    m.voxel_size = 0.2f;
    m.num_points = num_points;
    for (int i = 0; i < num_points; ++i) {
        m.x.push_back(v.F32());
        m.y.push_back(-v.F32());
        m.z.push_back(v.F32() * 1e-3f);
        m.intensity.push_back(v.F32());
    }
    return m;
}

ouster_stats_t MakeOusterStats() {
    Values v;
    ouster_stats_t m;
    m.schema_version = ouster_stats_t::SCHEMA_VERSION;
    m.sample_time_ns = v.I64();
    m.publish_time_ns = v.I64();
    m.counting_since_ns = v.I64();
    m.interval_start_time_ns = v.I64();
    m.prod_sn = 122'222'001'234;
    m.init_id = 5'431'292;
    m.lidar_packets_received = v.I64();
    m.lidar_packets_accepted = v.I64();
    m.imu_packets_received = v.I64();
    m.imu_packets_accepted = v.I64();
    m.bytes_received = v.I64();
    m.frames_complete = v.I64();
    m.frames_incomplete = v.I64();
    m.columns_lost = v.I64();
    m.packets_lost = v.I64();
    m.sensor_restarts = v.I64();
    m.rejected_wrong_size = v.I64();
    m.rejected_wrong_prod_sn = v.I64();
    m.rejected_wrong_init_id = v.I64();
    m.rejected_crc = v.I64();
    m.rejected_late = v.I64();
    m.rejected_unknown_port = v.I64();
    m.rejected_not_ouster = v.I64();
    m.crc_checked = v.I64();
    m.crc_failures = v.I64();
    m.latency_mean_ns = v.I64();
    m.latency_max_ns = v.I64();
    m.latency_frames = v.I64();
    return m;
}

go1_state_t MakeGo1State() {
    Values v;
    go1_state_t m;
    m.schema_version = go1_state_t::SCHEMA_VERSION;
    m.sample_time_ns = v.I64();
    m.publish_time_ns = v.I64();
    m.receive_time_ns = v.I64();
    m.alive_counter = 13;
    m.valid_groups = Bits(go1_state_t::GROUP_ALL) & ~Bits(go1_state_t::GROUP_ODOM_Z_YAW);
    m.fresh_groups = Bits(go1_state_t::GROUP_SYNC, go1_state_t::GROUP_IMU_GYRO);
    m.timed_out_groups = go1_state_t::GROUP_ODOM_Z_YAW;
    m.flags = Bits(go1_state_t::FLAG_SYNC_UDP_LINK_OK, go1_state_t::FLAG_ODOM_RESET,
                   go1_state_t::FLAG_STATUS_HIGHSTATE_CRC_OK);
    m.bridge_time_raw_us = 4'294'967'295;
    m.sample_age_us = 25'400;
    m.velocity_x = v.F32();
    m.velocity_y = -v.F32();
    m.yaw_rate = v.F32();
    m.velocity_z = -v.F32();
    m.body_height = v.F32();
    m.foot_raise_height = v.F32();
    v.Fill(m.gyro);
    v.Fill(m.accel);
    m.orientation_w = 0.875f;
    m.orientation_x = 0.25f;
    m.orientation_y = -0.125f;
    m.orientation_z = 0.3125f;
    m.foot_contact[go1_state_t::LEG_FR] = 1;
    m.foot_contact[go1_state_t::LEG_FL] = 0;
    m.foot_contact[go1_state_t::LEG_RR] = 0;
    m.foot_contact[go1_state_t::LEG_RL] = 1;
    v.Fill(m.foot_force_raw);
    v.Fill(m.odom_position);
    // The ODOM_Z_YAW group is timed out: its values are the documented invalid ones.
    m.odom_position[2] = kNaN;
    m.odom_yaw = std::numeric_limits<float>::quiet_NaN();
    m.mode = go1_state_t::MODE_RECOVERY_STAND;
    m.gait = go1_state_t::GAIT_CLIMB_STAIR;
    m.battery_soc_percent = 87;
    m.imu_temperature_degc = -12;
    m.udp_rx_lost = 254;
    m.bridge_state = go1_state_t::BRIDGE_STATE_DEGRADED;
    m.frames_received = v.I64();
    m.frames_unknown_id = v.I64();
    m.e2e_crc_errors = v.I64();
    m.e2e_counter_lost = v.I64();
    m.e2e_counter_repeats = v.I64();
    m.e2e_counter_resyncs = v.I64();
    m.e2e_timeouts = v.I64();
    return m;
}

imu_sample_t MakeImuSample(int32_t source) {
    Values v;
    imu_sample_t m;
    m.schema_version = imu_sample_t::SCHEMA_VERSION;
    m.sample_time_ns = v.I64();
    m.publish_time_ns = v.I64();
    m.source = source;
    m.sequence = v.I64();
    v.Fill(m.angular_velocity);
    v.Fill(m.linear_acceleration);
    if (source == imu_sample_t::SOURCE_OUSTER) {
        m.accel_time_offset_ns = -v.I64();
        m.flags = Bits(imu_sample_t::FLAG_ANGULAR_VELOCITY_VALID,
                       imu_sample_t::FLAG_LINEAR_ACCELERATION_VALID);
        // The Ouster has no orientation: NaN is the documented "absent".
        m.orientation_w = kNaN;
        m.orientation_x = kNaN;
        m.orientation_y = kNaN;
        m.orientation_z = kNaN;
    } else {
        m.accel_time_offset_ns = v.I64();
        m.flags = Bits(imu_sample_t::FLAG_ANGULAR_VELOCITY_VALID,
                       imu_sample_t::FLAG_ORIENTATION_VALID, imu_sample_t::FLAG_ACCEL_SATURATED);
        m.orientation_w = 0.5;
        m.orientation_x = 0.5;
        m.orientation_y = -0.5;
        m.orientation_z = 0.5;
    }
    return m;
}

rig_health_t MakeRigHealth() {
    Values v;
    rig_health_t m;
    m.schema_version = rig_health_t::SCHEMA_VERSION;
    m.sample_time_ns = v.I64();
    m.publish_time_ns = v.I64();
    m.interval_start_time_ns = v.I64();
    m.uptime_ns = v.I64();
    m.faults = rig_health_t::FAULT_LIDAR_REJECTS | rig_health_t::FAULT_DISK_LOW |
               rig_health_t::FAULT_LCM_PUBLISH;
    m.faults_latched = m.faults | rig_health_t::FAULT_CAN_E2E | rig_health_t::FAULT_CLOCK_JUMP;
    m.num_fault_counts = rig_health_t::NUM_FAULTS;
    for (int i = 0; i < m.num_fault_counts; ++i) {
        m.fault_counts.push_back(v.I64());
    }
    const char* threads[] = {"lidar_ingest", "can_ingest", "odometry", "keyframe_saver",
                             "lcm_bridge"};
    m.num_threads = static_cast<int32_t>(std::size(threads));
    for (const char* name : threads) {
        m.thread_name.push_back(v.Str(name));
        m.thread_cycles.push_back(v.I64());
        m.thread_deadline_misses.push_back(v.I64());
        m.thread_deadline_ns.push_back(v.I64());
        m.thread_max_cycle_ns.push_back(v.I64());
        m.thread_cpu_percent.push_back(v.F32());
        m.thread_stalls.push_back(v.I64());
    }
    const char* queues[] = {"packets", "scans", "keyframes"};
    m.num_queues = static_cast<int32_t>(std::size(queues));
    for (const char* name : queues) {
        m.queue_name.push_back(v.Str(name));
        m.queue_depth.push_back(v.I32());
        m.queue_max_depth.push_back(v.I32());
        m.queue_capacity.push_back(v.I32());
        m.queue_drops.push_back(v.I64());
    }
    m.process_cpu_percent = v.F32();
    m.process_rss_bytes = v.I64();
    m.disk_free_bytes = v.I64();
    m.session_bytes_written = v.I64();
    m.session_dir = "/data/sessions/2024-05-17T10-11-12Z_rig";
    return m;
}

// A classic frame of the Go1 bridge, and an extended CAN FD frame using every flag and byte.
can_frame_t MakeCanFrame(bool fd) {
    Values v;
    can_frame_t m;
    m.schema_version = can_frame_t::SCHEMA_VERSION;
    m.sample_time_ns = v.I64();
    m.publish_time_ns = v.I64();
    for (int i = 0; i < 64; ++i) {
        m.data[i] = 0;
    }
    if (fd) {
        m.id = 0x1abcdef0 + v.I16();
        m.flags = Bits(can_frame_t::FLAG_EFF, can_frame_t::FLAG_FD, can_frame_t::FLAG_FD_BRS,
                       can_frame_t::FLAG_FD_ESI);
        m.len = 64;
        for (int i = 0; i < 64; ++i) {
            m.data[i] = static_cast<uint8_t>(0xff - 3 * i);
        }
    } else {
        m.id = 0x130;
        m.flags = 0;
        m.len = 8;
        for (int i = 0; i < 8; ++i) {
            m.data[i] = static_cast<uint8_t>(0x11 * (i + 1));
        }
    }
    return m;
}

go1_bridge_status_t MakeGo1BridgeStatus() {
    Values v;
    go1_bridge_status_t m;
    m.schema_version = go1_bridge_status_t::SCHEMA_VERSION;
    m.sample_time_ns = v.I64();
    m.publish_time_ns = v.I64();
    m.uptime_ns = v.I64();
    m.sequence = v.I64();
    m.state = go1_bridge_status_t::STATE_DEGRADED;
    m.udp_link_ok = true;
    m.crc_check = false;
    m.crc_forms_seen = static_cast<int8_t>(go1_bridge_status_t::CRC_FORM_PLAIN |
                                           go1_bridge_status_t::CRC_FORM_SCRAMBLED);
    for (int64_t* counter :
         {&m.polls, &m.datagrams, &m.highstates_crc_plain, &m.highstates_crc_scrambled,
          &m.rejected_size, &m.rejected_head, &m.rejected_level_flag, &m.rejected_crc, &m.lost,
          &m.link_losses, &m.can_samples, &m.can_frames, &m.can_send_failures, &m.udp_errors}) {
        *counter = v.I64();
    }
    return m;
}

bim_pose_t MakeBimPose() {
    Values v;
    bim_pose_t m;
    m.schema_version = bim_pose_t::SCHEMA_VERSION;
    m.sample_time_ns = v.I64();
    m.publish_time_ns = v.I64();
    m.keyframe_time_ns = v.I64();
    m.state = bim_pose_t::STATE_LOCALISED;
    m.consistent_loops = v.I32();
    m.num_hypotheses = v.I32();
    v.Fill(m.position);
    v.Fill(m.orientation);
    v.Fill(m.pose_covariance);
    m.storey = v.Str("First Floor");
    m.space_name = v.Str("Office 1.04");
    m.space_global_id = v.Str("2O2Fr$t4X7Zf8NOew3FLOH");
    return m;
}

// ------------------------------------------------------------------------------------------------
// The messages each type is tested with.

template <class T>
std::vector<T> Samples();
template <>
std::vector<odometry_t> Samples() {
    return {MakeOdometry()};
}
template <>
std::vector<keyframe_t> Samples() {
    return {MakeKeyframe(257)};
}
template <>
std::vector<ouster_stats_t> Samples() {
    return {MakeOusterStats()};
}
template <>
std::vector<go1_state_t> Samples() {
    return {MakeGo1State()};
}
template <>
std::vector<imu_sample_t> Samples() {
    return {MakeImuSample(imu_sample_t::SOURCE_OUSTER), MakeImuSample(imu_sample_t::SOURCE_GO1)};
}
template <>
std::vector<rig_health_t> Samples() {
    return {MakeRigHealth()};
}
template <>
std::vector<go1_bridge_status_t> Samples() {
    return {MakeGo1BridgeStatus()};
}
template <>
std::vector<bim_pose_t> Samples() {
    return {MakeBimPose()};
}
template <>
std::vector<can_frame_t> Samples() {
    return {MakeCanFrame(false), MakeCanFrame(true)};
}

// Decodes `bytes` as a T and expects it to equal `sent`, field by field and byte for byte.
template <class T>
void ExpectDecodesTo(const Bytes& bytes, const T& sent) {
    T received;
    ASSERT_EQ(received.decode(bytes.data(), 0, static_cast<int>(bytes.size())),
              static_cast<int>(bytes.size()))
        << "decode failed or left bytes over";
    ExpectSameMessage(sent, received);
    EXPECT_EQ(bytes, Encode(sent)) << "received bytes differ from the sent encoding";
    EXPECT_EQ(Encode(received), bytes) << "re-encoding the decoded message changes the bytes";
}

// Collects the raw messages received on one channel.
class Collector {
public:
    void Handle(const lcm::ReceiveBuffer* rbuf, const std::string& /*channel*/) {
        const auto* data = static_cast<const uint8_t*>(rbuf->data);
        messages.emplace_back(data, data + rbuf->data_size);
    }
    std::vector<Bytes> messages;
};

// Publishes `msg` on a fresh channel of `lcm` and waits for it, publishing again (up to 5 times)
// when a datagram was lost. Returns the bytes received, or nothing.
template <class T>
std::vector<Bytes> PublishAndReceive(lcm::LCM& lcm, const T& msg, const std::string& what) {
    const std::string channel = UniqueChannel(what);
    Collector collector;
    lcm::Subscription* sub = lcm.subscribe(channel, &Collector::Handle, &collector);
    for (int attempt = 0; attempt < 5 && collector.messages.empty(); ++attempt) {
        EXPECT_EQ(lcm.publish(channel, &msg), 0) << "publish failed, attempt " << attempt;
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(400);
        while (collector.messages.empty() && std::chrono::steady_clock::now() < deadline) {
            const int rc = lcm.handleTimeout(50);
            EXPECT_GE(rc, 0) << "lcm.handleTimeout failed";
            if (rc < 0) break;
        }
    }
    lcm.unsubscribe(sub);
    return collector.messages;
}

// Why an udpm:// instance is not good(): the test fails (never skips) and says what to do.
std::string MulticastHint(const std::string& url) {
    return "cannot open LCM at " + url +
           ": UDP multicast is not usable on this machine. Run toolchain/setup-multicast.sh (as "
           "root) to route 224.0.0.0/4, then rerun the test.";
}

template <class T>
class LcmRoundTrip : public ::testing::Test {};

using MessageTypes =
    ::testing::Types<odometry_t, keyframe_t, ouster_stats_t, go1_state_t, imu_sample_t,
                     rig_health_t, can_frame_t, go1_bridge_status_t, bim_pose_t>;

// Short type names for channel names. (No gtest name generator: ctest's test discovery in
// CMake 3.25 only understands the default numbered typed-suite names, which it shows as
// "LcmRoundTrip.OverUdpMulticast<bimslam::odometry_t>".)
template <class T>
std::string TypeName() {
    if (std::is_same_v<T, odometry_t>) return "odometry_t";
    if (std::is_same_v<T, keyframe_t>) return "keyframe_t";
    if (std::is_same_v<T, ouster_stats_t>) return "ouster_stats_t";
    if (std::is_same_v<T, go1_state_t>) return "go1_state_t";
    if (std::is_same_v<T, imu_sample_t>) return "imu_sample_t";
    if (std::is_same_v<T, rig_health_t>) return "rig_health_t";
    if (std::is_same_v<T, can_frame_t>) return "can_frame_t";
    if (std::is_same_v<T, go1_bridge_status_t>) return "go1_bridge_status_t";
    if (std::is_same_v<T, bim_pose_t>) return "bim_pose_t";
    return "unknown";
}

TYPED_TEST_SUITE(LcmRoundTrip, MessageTypes);

TYPED_TEST(LcmRoundTrip, EncodesAndDecodesInMemory) {
    for (const TypeParam& msg : Samples<TypeParam>()) {
        EXPECT_EQ(msg.schema_version, static_cast<int32_t>(TypeParam::SCHEMA_VERSION));
        ExpectDecodesTo(Encode(msg), msg);
    }
}

TYPED_TEST(LcmRoundTrip, OverUdpMulticast) {
    lcm::LCM lcm(kUdpmUrl);
    ASSERT_TRUE(lcm.good()) << MulticastHint(kUdpmUrl);
    for (const TypeParam& msg : Samples<TypeParam>()) {
        const std::vector<Bytes> received = PublishAndReceive(lcm, msg, TypeName<TypeParam>());
        ASSERT_FALSE(received.empty()) << "nothing received over " << kUdpmUrl << " after 5 tries";
        ExpectDecodesTo(received.front(), msg);
    }
}

TYPED_TEST(LcmRoundTrip, ThroughLogFile) {
    const test::TempDir dir;
    const std::string path = (dir / "round_trip.lcmlog").string();
    const std::string channel = UniqueChannel(TypeName<TypeParam>());
    const std::vector<TypeParam> sent = Samples<TypeParam>();
    {
        const std::string url = "file://" + path + "?mode=w";
        lcm::LCM writer(url);
        ASSERT_TRUE(writer.good()) << "cannot open " << url;
        for (const TypeParam& msg : sent) {
            ASSERT_EQ(writer.publish(channel, &msg), 0);
        }
    }  // closes the log
    lcm::LogFile log(path, "r");
    ASSERT_TRUE(log.good()) << "cannot read " << path;
    for (const TypeParam& msg : sent) {
        const lcm::LogEvent* event = log.readNextEvent();
        ASSERT_NE(event, nullptr) << path << " ends early";
        EXPECT_EQ(event->channel, channel);
        const auto* data = static_cast<const uint8_t*>(event->data);
        ExpectDecodesTo(Bytes(data, data + event->datalen), msg);
    }
    EXPECT_EQ(log.readNextEvent(), nullptr) << path << " holds more events than were published";
}

// ------------------------------------------------------------------------------------------------
// A 20 000-point keyframe (~320 kB encoded) overflows the default socket receive buffer; with
// recv_buf_size raised in the URL it arrives whole.

TEST(LcmBigKeyframe, OverUdpMulticastWithRaisedReceiveBuffer) {
    const keyframe_t msg = MakeKeyframe(kBigKeyframePoints);
    ASSERT_GT(msg.getEncodedSize(), 300'000);
    {
        std::ifstream rmem_max("/proc/sys/net/core/rmem_max");
        int64_t limit = 0;
        if (rmem_max >> limit && limit < 4194304) {
            std::cout << "note: net.core.rmem_max is " << limit
                      << " B, below the 4 MiB recv_buf_size asked for; the kernel caps it\n";
        }
    }
    lcm::LCM lcm(kUdpmBigUrl);
    ASSERT_TRUE(lcm.good()) << MulticastHint(kUdpmBigUrl);
    const std::vector<Bytes> received = PublishAndReceive(lcm, msg, "big_keyframe");
    ASSERT_FALSE(received.empty()) << "nothing received over " << kUdpmBigUrl << " after 5 tries";
    ExpectDecodesTo(received.front(), msg);
}

TEST(LcmBigKeyframe, ThroughLogFile) {
    const keyframe_t msg = MakeKeyframe(kBigKeyframePoints);
    const test::TempDir dir;
    const std::string path = (dir / "big.lcmlog").string();
    {
        lcm::LCM writer("file://" + path + "?mode=w");
        ASSERT_TRUE(writer.good());
        ASSERT_EQ(writer.publish("BIMSLAM_KEYFRAME", &msg), 0);
    }
    lcm::LCM reader("file://" + path + "?mode=r&speed=0");
    ASSERT_TRUE(reader.good());
    Collector collector;
    reader.subscribe("BIMSLAM_KEYFRAME", &Collector::Handle, &collector);
    ASSERT_GT(reader.handleTimeout(2000), 0) << "nothing read back from " << path;
    ASSERT_EQ(collector.messages.size(), 1u);
    ExpectDecodesTo(collector.messages.front(), msg);
}

// ------------------------------------------------------------------------------------------------
// Constants the publishers and readers rely on.

TEST(LcmConstants, AreConsistent) {
    EXPECT_EQ(static_cast<int32_t>(odometry_t::SCHEMA_VERSION), 1);
    EXPECT_EQ(static_cast<int32_t>(keyframe_t::SCHEMA_VERSION), 1);
    EXPECT_EQ(static_cast<int32_t>(ouster_stats_t::SCHEMA_VERSION), 1);
    EXPECT_EQ(static_cast<int32_t>(go1_state_t::SCHEMA_VERSION), 1);
    EXPECT_EQ(static_cast<int32_t>(imu_sample_t::SCHEMA_VERSION), 1);
    EXPECT_EQ(static_cast<int32_t>(rig_health_t::SCHEMA_VERSION), 3);  // + FAULT_BIM_MAP
    EXPECT_EQ(static_cast<int32_t>(can_frame_t::SCHEMA_VERSION), 1);
    EXPECT_EQ(static_cast<int32_t>(bim_pose_t::SCHEMA_VERSION), 1);
    // bim_pose_t: the STATE_* values are RelocalizerState's order (firmware/modules/lcm_bridge).
    const int8_t states[] = {bim_pose_t::STATE_SEARCHING, bim_pose_t::STATE_CANDIDATE,
                             bim_pose_t::STATE_LOCALISED, bim_pose_t::STATE_AMBIGUOUS,
                             bim_pose_t::STATE_LOST};
    for (size_t i = 0; i < std::size(states); ++i) EXPECT_EQ(states[i], int8_t(i));

    // can_frame_t: the FLAG_* bits are distinct single bits.
    const int32_t can_flags[] = {can_frame_t::FLAG_EFF,    can_frame_t::FLAG_RTR,
                                 can_frame_t::FLAG_ERR,    can_frame_t::FLAG_FD,
                                 can_frame_t::FLAG_FD_BRS, can_frame_t::FLAG_FD_ESI};
    int32_t can_all = 0;
    for (int32_t f : can_flags) {
        EXPECT_EQ(f & (f - 1), 0) << "not a single bit: " << f;
        EXPECT_EQ(can_all & f, 0) << "flag bits overlap";
        can_all |= f;
    }

    const int32_t groups[] = {go1_state_t::GROUP_SYNC,       go1_state_t::GROUP_BODY_VEL,
                              go1_state_t::GROUP_BODY_STATE, go1_state_t::GROUP_IMU_GYRO,
                              go1_state_t::GROUP_IMU_ACCEL,  go1_state_t::GROUP_IMU_QUAT,
                              go1_state_t::GROUP_FOOT,       go1_state_t::GROUP_ODOM_XY,
                              go1_state_t::GROUP_ODOM_Z_YAW, go1_state_t::GROUP_STATUS};
    int32_t all = 0;
    for (int32_t g : groups) {
        EXPECT_EQ(all & g, 0) << "group bits overlap";
        all |= g;
    }
    EXPECT_EQ(all, static_cast<int32_t>(go1_state_t::GROUP_ALL));

    // rig_health_t: fault bit i is (1 << i) for i < NUM_FAULTS, highest last.
    const int64_t faults[] = {rig_health_t::FAULT_LIDAR_TIMEOUT,
                              rig_health_t::FAULT_LIDAR_REJECTS,
                              rig_health_t::FAULT_LIDAR_INCOMPLETE,
                              rig_health_t::FAULT_LIDAR_RESTART,
                              rig_health_t::FAULT_IMU_TIMEOUT,
                              rig_health_t::FAULT_CAN_TIMEOUT,
                              rig_health_t::FAULT_CAN_E2E,
                              rig_health_t::FAULT_GO1_BRIDGE,
                              rig_health_t::FAULT_DEADLINE_MISS,
                              rig_health_t::FAULT_QUEUE_OVERFLOW,
                              rig_health_t::FAULT_CPU_OVERLOAD,
                              rig_health_t::FAULT_DISK_LOW,
                              rig_health_t::FAULT_DISK_WRITE,
                              rig_health_t::FAULT_ODOMETRY_DEGENERATE,
                              rig_health_t::FAULT_ODOMETRY_OVER_BUDGET,
                              rig_health_t::FAULT_ODOMETRY_LOST,
                              rig_health_t::FAULT_CLOCK_JUMP,
                              rig_health_t::FAULT_CONFIG,
                              rig_health_t::FAULT_LCM_PUBLISH,
                              rig_health_t::FAULT_THREAD_STALLED,
                              rig_health_t::FAULT_BIM_MAP,
                              rig_health_t::FAULT_BIM_LOST};
    ASSERT_EQ(static_cast<int32_t>(std::size(faults)),
              static_cast<int32_t>(rig_health_t::NUM_FAULTS));
    for (size_t i = 0; i < std::size(faults); ++i) {
        EXPECT_EQ(faults[i], int64_t{1} << i) << "fault " << i;
    }

    // Every type has its own fingerprint.
    const int64_t hashes[] = {odometry_t::getHash(),     keyframe_t::getHash(),
                              ouster_stats_t::getHash(), go1_state_t::getHash(),
                              imu_sample_t::getHash(),   rig_health_t::getHash(),
                              can_frame_t::getHash(),    bim_pose_t::getHash()};
    for (size_t i = 0; i < std::size(hashes); ++i) {
        for (size_t j = i + 1; j < std::size(hashes); ++j) {
            EXPECT_NE(hashes[i], hashes[j]) << i << " vs " << j;
        }
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::lcmtypes
