// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// One Go1 HighState sample as it arrives over CAN (specs/go1-can.md, drivers/can/
// go1_odometry.dbc): every signal in physical SI units, with the validity of each message group.
// Plain data, no allocation; the decoder fills it, the bridge's encoder reads it.
#pragma once

#include <array>
#include <cstdint>

namespace bimslam::can {

// One bit per DBC message (group of signals).
enum Go1Group : uint16_t {
    kGroupSync = 1 << 0,       // GO1_SYNC 0x0F0
    kGroupBodyVel = 1 << 1,    // GO1_BODY_VEL 0x100
    kGroupBodyState = 1 << 2,  // GO1_BODY_STATE 0x101
    kGroupGyro = 1 << 3,       // GO1_IMU_GYRO 0x110
    kGroupAccel = 1 << 4,      // GO1_IMU_ACCEL 0x111
    kGroupQuat = 1 << 5,       // GO1_IMU_QUAT 0x112
    kGroupFoot = 1 << 6,       // GO1_FOOT 0x120
    kGroupOdomXy = 1 << 7,     // GO1_ODOM_XY 0x130
    kGroupOdomZYaw = 1 << 8,   // GO1_ODOM_Z_YAW 0x131
    kGroupStatus = 1 << 9,     // GO1_STATUS 0x140
};
inline constexpr uint16_t kAllGroups = (1 << 10) - 1;

struct Go1Sample {
    uint8_t counter = 0;           // alive counter 0..14 shared by the sample's frames
    int64_t bridge_time_ns = 0;    // SYNC BridgeTime (bridge CLOCK_MONOTONIC), unwrapped to ns
    int64_t host_time_ns = 0;      // receive time of the frame that completed the sample
    uint32_t sample_age_us = 0;    // SYNC SampleAge: UDP receive to CAN transmit, µs
    bool udp_link_ok = false;      // SYNC/STATUS UdpLinkOk
    bool highstate_crc_ok = false; // SYNC/STATUS HighStateCrcOk

    uint16_t valid = 0;  // Go1Group bits: signals of the group usable (received, Valid bit set,
                         // not SNA, not timed out)
    uint16_t fresh = 0;  // Go1Group bits: frames with this sample's counter were received

    // GO1_BODY_VEL, GO1_BODY_STATE: body frame (x forward, y left, z up).
    double vx = 0, vy = 0;       // m/s
    double yaw_rate = 0;         // rad/s
    double vz = 0;               // m/s (informational, see the DBC comment)
    double body_height = 0;      // m
    double foot_raise_height = 0;  // m

    // GO1_IMU_*: raw IMU in the IMU's frame (the body frame on the Go1).
    std::array<double, 3> gyro{};   // rad/s
    std::array<double, 3> accel{};  // m/s^2 (specific force)
    bool gyro_saturated = false, accel_saturated = false;
    std::array<double, 4> quat_wxyz{1, 0, 0, 0};  // w reconstructed: sqrt(max(0, 1-x^2-y^2-z^2))

    // GO1_FOOT: legs FR, FL, RR, RL.
    std::array<bool, 4> foot_contact{};
    std::array<uint16_t, 4> foot_force_raw{};

    // GO1_ODOM_*: Unitree's own drifting odometry, from 0 at boot.
    double odom_x = 0, odom_y = 0, odom_z = 0;  // m
    double odom_yaw = 0;                        // rad
    bool odom_reset = false;                    // a discontinuity (reboot, jump)

    // GO1_STATUS.
    uint8_t mode = 0, gait = 0, bridge_state = 0;
    uint8_t battery_soc = 0;  // %
    int8_t imu_temperature_c = 0;
    uint8_t udp_rx_lost = 0;  // HighState samples the bridge missed since the last STATUS
};

}  // namespace bimslam::can
