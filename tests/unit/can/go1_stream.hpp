// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Test helpers: random Go1 samples and the frame stream a bridge would send for them.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "algorithms/common/can_frame.hpp"
#include "drivers/can/go1_encoder.hpp"
#include "drivers/can/go1_sample.hpp"

namespace bimslam::can::testing {

inline constexpr int64_t kTickNs = 5'000'000;
inline constexpr int64_t kSpacingNs = 230'000;  // an 8-byte frame at 500 kbit/s

// Plausible values, every group valid.
inline Go1Sample RandomSample(std::mt19937& rng, int64_t bridge_time_ns) {
    auto u = [&](double lo, double hi) {
        return std::uniform_real_distribution<double>(lo, hi)(rng);
    };
    auto bit = [&] { return (rng() & 1) != 0; };
    Go1Sample s;
    s.bridge_time_ns = bridge_time_ns;
    s.sample_age_us = static_cast<uint32_t>(rng() % 25401);
    s.udp_link_ok = bit();
    s.highstate_crc_ok = bit();
    s.valid = kAllGroups;
    s.vx = u(-3, 3);
    s.vy = u(-1, 1);
    s.yaw_rate = u(-2, 2);
    s.vz = u(-0.5, 0.5);
    s.body_height = u(0.2, 0.4);
    s.foot_raise_height = u(0, 0.15);
    for (auto& g : s.gyro) g = u(-5, 5);
    for (auto& a : s.accel) a = u(-20, 20);
    s.gyro_saturated = bit();
    s.accel_saturated = bit();
    double n = 0;
    std::array<double, 4> q;
    do {
        for (auto& c : q) c = u(-1, 1);
        n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    } while (n < 0.1 || n > 1.0);
    for (size_t i = 0; i < 4; ++i) s.quat_wxyz[i] = q[i] / n;
    for (auto& c : s.foot_contact) c = bit();
    for (auto& f : s.foot_force_raw) f = static_cast<uint16_t>(rng() % 4095);
    s.odom_x = u(-100, 100);
    s.odom_y = u(-100, 100);
    s.odom_z = u(-1, 1);
    s.odom_yaw = u(-3.14, 3.14);
    s.odom_reset = rng() % 50 == 0;
    s.mode = static_cast<uint8_t>(rng() % 12);
    s.gait = static_cast<uint8_t>(rng() % 5);
    s.bridge_state = static_cast<uint8_t>(rng() % 4);
    s.battery_soc = static_cast<uint8_t>(rng() % 101);
    s.imu_temperature_c = static_cast<int8_t>(static_cast<int>(rng() % 100) - 20);
    s.udp_rx_lost = static_cast<uint8_t>(rng() % 10);
    return s;
}

// What a bridge sends for n random samples: a tick every 5 ms from t0, frames 0.23 ms apart.
struct Stream {
    std::vector<common::CanFrame> frames;
    std::vector<size_t> sample_of_frame;  // index into samples
    std::vector<Go1Sample> samples;       // as given to the encoder
    std::vector<uint16_t> groups;         // Go1Group bits sent with each sample
    std::vector<int64_t> last_frame_ns;   // receive time of each sample's last first-tick frame
};

inline Stream MakeStream(int n, uint32_t seed, int64_t t0_ns = 1'000'000'000,
                         int64_t bridge0_ns = 5'000'000'000) {
    std::mt19937 rng(seed);
    Go1EncoderConfig config;
    config.frame_spacing_ns = kSpacingNs;
    Go1Encoder encoder(config);
    Stream st;
    std::array<common::CanFrame, Go1Encoder::kMaxFramesPerTick> out;
    for (int tick = 0; tick < 2 * n; ++tick) {
        const int64_t t = t0_ns + int64_t{tick} * kTickNs;
        const bool starts = encoder.sample_tick_next();
        if (starts) {
            // The bridge's clock: 10 ms per sample plus jitter of the UDP receive.
            st.samples.push_back(RandomSample(rng, bridge0_ns + int64_t{tick / 2} * 10'000'000 +
                                                       static_cast<int64_t>(rng() % 2000'000)));
            st.groups.push_back(encoder.NextSampleGroups());
        }
        const size_t k = encoder.Tick(&st.samples.back(), t, out);
        for (size_t i = 0; i < k; ++i) {
            st.frames.push_back(out[i]);
            st.sample_of_frame.push_back(st.samples.size() - 1);
        }
        if (starts) st.last_frame_ns.push_back(out[k - 1].timestamp_ns);
    }
    return st;
}

// The decoded sample equals the truth within half a raw step, for the groups in `groups`.
inline void ExpectSameValues(const Go1Sample& got, const Go1Sample& truth, uint16_t groups) {
    const double mm = 0.0005 + 1e-9;  // half of 0.001
    if (groups & kGroupSync) {
        EXPECT_EQ(got.udp_link_ok, truth.udp_link_ok);
        EXPECT_EQ(got.highstate_crc_ok, truth.highstate_crc_ok);
        EXPECT_NEAR(got.sample_age_us, truth.sample_age_us, 50);
    }
    if (groups & kGroupBodyVel) {
        EXPECT_NEAR(got.vx, truth.vx, mm);
        EXPECT_NEAR(got.vy, truth.vy, mm);
        EXPECT_NEAR(got.yaw_rate, truth.yaw_rate, mm);
    }
    if (groups & kGroupBodyState) {
        EXPECT_NEAR(got.vz, truth.vz, mm);
        EXPECT_NEAR(got.body_height, truth.body_height, mm);
        EXPECT_NEAR(got.foot_raise_height, truth.foot_raise_height, mm);
    }
    if (groups & kGroupGyro) {
        EXPECT_EQ(got.gyro_saturated, truth.gyro_saturated);
        for (size_t i = 0; i < 3; ++i) EXPECT_NEAR(got.gyro[i], truth.gyro[i], mm);
    }
    if (groups & kGroupAccel) {
        EXPECT_EQ(got.accel_saturated, truth.accel_saturated);
        for (size_t i = 0; i < 3; ++i) EXPECT_NEAR(got.accel[i], truth.accel[i], 0.0025 + 1e-9);
    }
    if (groups & kGroupQuat) {
        // The bridge sends the w >= 0 representative; w comes back from x, y, z, so its error
        // grows as w shrinks (d w = -(x dx + y dy + z dz) / w).
        const double sign = truth.quat_wxyz[0] < 0 ? -1.0 : 1.0;
        const double half_step = std::ldexp(1.0, -16) + 1e-12;
        for (size_t i = 1; i < 4; ++i) {
            EXPECT_NEAR(got.quat_wxyz[i], sign * truth.quat_wxyz[i], half_step);
        }
        const double w = sign * truth.quat_wxyz[0];
        EXPECT_NEAR(got.quat_wxyz[0], w, w > 0.05 ? 2.0 * half_step / w : 0.02);
    }
    if (groups & kGroupFoot) {
        EXPECT_EQ(got.foot_contact, truth.foot_contact);
        EXPECT_EQ(got.foot_force_raw, truth.foot_force_raw);
    }
    if (groups & kGroupOdomXy) {
        EXPECT_NEAR(got.odom_x, truth.odom_x, mm);
        EXPECT_NEAR(got.odom_y, truth.odom_y, mm);
        EXPECT_EQ(got.odom_reset, truth.odom_reset);
    }
    if (groups & kGroupOdomZYaw) {
        EXPECT_NEAR(got.odom_z, truth.odom_z, mm);
        EXPECT_NEAR(got.odom_yaw, truth.odom_yaw, 0.00005 + 1e-9);
    }
    if (groups & kGroupStatus) {
        EXPECT_EQ(got.mode, truth.mode);
        EXPECT_EQ(got.gait, truth.gait);
        EXPECT_EQ(got.bridge_state, truth.bridge_state);
        EXPECT_EQ(got.battery_soc, truth.battery_soc);
        EXPECT_EQ(got.imu_temperature_c, truth.imu_temperature_c);
        EXPECT_EQ(got.udp_rx_lost, truth.udp_rx_lost);
    }
}

}  // namespace bimslam::can::testing
