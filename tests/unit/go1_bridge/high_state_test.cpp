// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// HighState / HighCmd: layout facts of unitree_legged_sdk (go1 branch, comm.h), Unitree's CRC-32,
// the SDK's scrambled CRC form, parse(serialize(x)) == x, rejection of wrong sizes, heads,
// levelFlags and bad CRCs.
#include "drivers/go1/high_state.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <random>
#include <tuple>
#include <vector>

namespace bimslam::go1_bridge {
namespace {
namespace BIMSLAM_UNITY_ID {
using namespace ::bimslam::go1;  // the HighState codec (drivers/go1)

// CRC-32/MPEG-2 (poly 0x04C11DB7, init 0xFFFFFFFF, no reflection, no xorout), byte-wise: an
// independent reference for Unitree's word-wise routine.
uint32_t Mpeg2Crc(const uint8_t* data, size_t n) {
    uint32_t crc = 0xffffffff;
    for (size_t i = 0; i < n; ++i) {
        crc ^= static_cast<uint32_t>(data[i]) << 24;
        for (int b = 0; b < 8; ++b) {
            crc = (crc & 0x80000000u) ? (crc << 1) ^ 0x04c11db7u : crc << 1;
        }
    }
    return crc;
}

// A HighState with every field set to a distinct value.
HighState MakeState() {
    HighState s;
    int k = 1;
    auto f = [&k]() { return 0.125f * static_cast<float>(k++) - 3.0f; };
    auto u8 = [&k]() { return static_cast<uint8_t>(k++ * 7); };
    s.head = {0xfe, 0xef};
    s.level_flag = kHighLevel;
    s.frame_reserve = u8();
    s.sn = {0x01020304u, 0xa0b0c0d0u};
    s.version = {0x11223344u, 0x55667788u};
    s.band_width = 0x3ac0;
    for (float& v : s.imu.quaternion) v = f();
    for (float& v : s.imu.gyroscope) v = f();
    for (float& v : s.imu.accelerometer) v = f();
    for (float& v : s.imu.rpy) v = f();
    s.imu.temperature = -17;
    for (MotorState& m : s.motor_state) {
        m.mode = u8();
        m.q = f();
        m.dq = f();
        m.ddq = f();
        m.tau_est = f();
        m.q_raw = f();
        m.dq_raw = f();
        m.ddq_raw = f();
        m.temperature = static_cast<int8_t>(-(k++ % 100));
        m.reserve = {static_cast<uint32_t>(k++) * 0x01010101u, 0xdeadbeefu};
    }
    s.bms =
        BmsState{2,       3,       4,
                 87,      -12345,  321,
                 {-5, 6}, {7, -8}, {3700, 3701, 3702, 3703, 3704, 3705, 3706, 3707, 3708, 3709}};
    s.foot_force = {-3, 100, 2000, 32767};
    s.foot_force_est = {-32768, 5, 6, 7};
    s.mode = 2;
    s.progress = f();
    s.gait_type = 1;
    s.foot_raise_height = 0.08f;
    s.position = {12.5f, -7.25f, 0.03125f};
    s.body_height = 0.28f;
    s.velocity = {0.5f, -0.25f, 0.0625f};
    s.yaw_speed = -1.5f;
    for (float& v : s.range_obstacle) v = f();
    for (Cartesian& c : s.foot_position_2_body) c = {f(), f(), f()};
    for (Cartesian& c : s.foot_speed_2_body) c = {f(), f(), f()};
    for (uint8_t& b : s.wireless_remote) b = u8();
    s.reserve = 0x0badf00d;
    return s;
}

float FloatAt(const std::array<uint8_t, kHighStateSize>& b, size_t at) {
    uint32_t u = 0;
    for (size_t i = 0; i < 4; ++i) u |= static_cast<uint32_t>(b[at + i]) << (8 * i);
    float v;
    std::memcpy(&v, &u, 4);
    return v;
}

TEST(HighStateLayout, SizesAndOffsetsOfTheSdkHeader) {
    EXPECT_EQ(kHighStateSize, 1087u);
    EXPECT_EQ(kHighCmdSize, 129u);
    EXPECT_EQ(layout::kImuSize, 53u);
    EXPECT_EQ(layout::kMotorStateSize, 38u);
    EXPECT_EQ(layout::kBmsStateSize, 34u);
    EXPECT_EQ(layout::hs::kImu, 22u);
    EXPECT_EQ(layout::hs::kMotorState, 75u);
    EXPECT_EQ(layout::hs::kBms, 835u);
    EXPECT_EQ(layout::hs::kFootForce, 869u);
    EXPECT_EQ(layout::hs::kFootForceEst, 877u);
    EXPECT_EQ(layout::hs::kMode, 885u);
    EXPECT_EQ(layout::hs::kProgress, 886u);
    EXPECT_EQ(layout::hs::kGaitType, 890u);
    EXPECT_EQ(layout::hs::kFootRaiseHeight, 891u);
    EXPECT_EQ(layout::hs::kPosition, 895u);
    EXPECT_EQ(layout::hs::kBodyHeight, 907u);
    EXPECT_EQ(layout::hs::kVelocity, 911u);
    EXPECT_EQ(layout::hs::kYawSpeed, 923u);
    EXPECT_EQ(layout::hs::kRangeObstacle, 927u);
    EXPECT_EQ(layout::hs::kFootPosition2Body, 943u);
    EXPECT_EQ(layout::hs::kFootSpeed2Body, 991u);
    EXPECT_EQ(layout::hs::kWirelessRemote, 1039u);
    EXPECT_EQ(layout::hs::kReserve, 1079u);
    EXPECT_EQ(layout::hs::kCrc, 1083u);
    EXPECT_EQ(layout::hc::kMode, 22u);
    EXPECT_EQ(layout::hc::kFootRaiseHeight, 25u);
    EXPECT_EQ(layout::hc::kYawSpeed, 61u);
    EXPECT_EQ(layout::hc::kLed, 69u);
    EXPECT_EQ(layout::hc::kWirelessRemote, 81u);
    EXPECT_EQ(layout::hc::kCrc, 125u);
}

TEST(UnitreeCrc, IsMpeg2OverByteSwappedWords) {
    // The check value of CRC-32/MPEG-2.
    const char* check = "123456789";
    EXPECT_EQ(Mpeg2Crc(reinterpret_cast<const uint8_t*>(check), 9), 0x0376e6e7u);
    // Unitree's routine reads little-endian words and feeds them MSB first.
    std::mt19937 rng(7);
    for (int n = 0; n < 20; ++n) {
        std::vector<uint8_t> bytes(4 * static_cast<size_t>(n));
        for (uint8_t& b : bytes) b = static_cast<uint8_t>(rng());
        std::vector<uint8_t> swapped(bytes.size());
        for (size_t i = 0; i < bytes.size(); i += 4) {
            for (size_t j = 0; j < 4; ++j) swapped[i + j] = bytes[i + 3 - j];
        }
        EXPECT_EQ(UnitreeCrc32(bytes), Mpeg2Crc(swapped.data(), swapped.size())) << n;
    }
    // Values worked out by hand (Python, bit by bit).
    const std::array<uint8_t, 4> zero{0, 0, 0, 0};
    const std::array<uint8_t, 4> one{1, 0, 0, 0};
    EXPECT_EQ(UnitreeCrc32(zero), 0xc704dd7bu);
    EXPECT_EQ(UnitreeCrc32(one), 0xc3c5c0ccu);
    EXPECT_EQ(UnitreeCrc32({}), 0xffffffffu);
    // A trailing partial word is not read.
    const std::array<uint8_t, 7> seven{1, 0, 0, 0, 9, 9, 9};
    EXPECT_EQ(UnitreeCrc32(seven), 0xc3c5c0ccu);
}

TEST(HighState, HandBuiltPacketHasTheCrcComputedByHand) {
    // Zeros except head FE EF, levelFlag 0xEE, bms.SOC = 87 and position[0] = 1.5f.
    std::array<uint8_t, kHighStateSize> bytes{};
    bytes[0] = 0xfe;
    bytes[1] = 0xef;
    bytes[2] = 0xee;
    bytes[layout::hs::kBms + 3] = 87;
    const std::array<uint8_t, 4> one_and_a_half{0x00, 0x00, 0xc0, 0x3f};  // 1.5f little-endian
    std::copy(one_and_a_half.begin(), one_and_a_half.end(), bytes.begin() + layout::hs::kPosition);
    const uint32_t expected = 0x7f8a10a2;  // Python reference, first 1080 bytes
    for (size_t i = 0; i < 4; ++i) {
        bytes[layout::hs::kCrc + i] = static_cast<uint8_t>(expected >> (8 * i));
    }
    HighState s;
    ASSERT_EQ(ParseHighState(bytes, s), ParseResult::kOk);
    EXPECT_EQ(s.crc, expected);
    EXPECT_EQ(s.level_flag, kHighLevel);
    EXPECT_EQ(s.bms.soc, 87);
    EXPECT_EQ(s.position[0], 1.5f);

    // Our serialiser writes the same bytes.
    std::array<uint8_t, kHighStateSize> written{};
    EXPECT_EQ(SerializeHighState(s, written), expected);
    EXPECT_EQ(written, bytes);

    // The 3 bytes after the covered 1080 (the end of `reserve`) are outside the CRC; the CRC's
    // own bytes and everything before are inside.
    bytes[1081] ^= 0x5a;
    EXPECT_EQ(ParseHighState(bytes, s), ParseResult::kOk);
    bytes[1079] ^= 0x01;
    EXPECT_EQ(ParseHighState(bytes, s), ParseResult::kBadCrc);
}

TEST(HighState, ParseOfSerializeIsIdentity) {
    HighState s = MakeState();
    std::array<uint8_t, kHighStateSize> bytes{};
    s.crc = SerializeHighState(s, bytes);
    HighState parsed;
    ASSERT_EQ(ParseHighState(bytes, parsed), ParseResult::kOk);
    EXPECT_TRUE(parsed == s);
    EXPECT_EQ(parsed.imu.temperature, -17);
    EXPECT_EQ(parsed.foot_force[3], 32767);
    EXPECT_EQ(parsed.bms.current, -12345);
    // Fields land where the SDK header puts them.
    EXPECT_EQ(FloatAt(bytes, layout::hs::kPosition + 4), -7.25f);
    EXPECT_EQ(FloatAt(bytes, layout::hs::kYawSpeed), -1.5f);
    EXPECT_EQ(FloatAt(bytes, layout::hs::kBodyHeight), 0.28f);
    EXPECT_EQ(FloatAt(bytes, layout::hs::kImu + layout::kImuQuaternion), s.imu.quaternion[0]);
    EXPECT_EQ(bytes[layout::hs::kMode], 2);
    EXPECT_EQ(bytes[layout::hs::kGaitType], 1);
    EXPECT_EQ(bytes[layout::hs::kBms + 3], 87);
    EXPECT_EQ(static_cast<int8_t>(bytes[layout::hs::kImu + layout::kImuTemperature]), -17);
}

TEST(HighState, RejectsWrongSizeAndEveryCorruptedByte) {
    HighState s = MakeState();
    std::array<uint8_t, kHighStateSize> bytes{};
    SerializeHighState(s, bytes);
    HighState parsed;
    EXPECT_EQ(ParseHighState(std::span<const uint8_t>(bytes).first(1086), parsed),
              ParseResult::kWrongSize);
    std::vector<uint8_t> longer(bytes.begin(), bytes.end());
    longer.push_back(0);
    EXPECT_EQ(ParseHighState(longer, parsed), ParseResult::kWrongSize);
    EXPECT_EQ(ParseHighState({}, parsed), ParseResult::kWrongSize);
    // Past the head and levelFlag (checked first, below), every covered byte is in the CRC.
    for (size_t i = layout::kFrameReserve; i < kHighStateSize; ++i) {
        if (i >= layout::hs::kCrcCoveredBytes && i < layout::hs::kCrc) continue;  // not covered
        auto damaged = bytes;
        damaged[i] ^= 0x10;
        ASSERT_EQ(ParseHighState(damaged, parsed), ParseResult::kBadCrc) << "byte " << i;
    }
    EXPECT_STREQ(ToString(ParseResult::kBadCrc), "bad CRC");
}

// The SDK's encryptCRC on known vectors, worked by hand from its definition, stored =
// rotr32(crc ^ 0xEDCAB9DE, 8), i.e. the bytes [b, c, d, a] of crc ^ K = [a, b, c, d]
// little-endian:
// - crc 0x00000000: crc ^ K = 0xEDCAB9DE, bytes [DE B9 CA ED] -> [B9 CA ED DE] = 0xDEEDCAB9.
// - crc 0x7F8A10A2 (the reference HighState above): 7F^ED = 92, 8A^CA = 40, 10^B9 = A9,
//   A2^DE = 7C, so crc ^ K = 0x9240A97C, bytes [7C A9 40 92] -> [A9 40 92 7C] = 0x7C9240A9.
// - crc 0xD8FC0F0B (the idle HighCmd below): D8^ED = 35, FC^CA = 36, 0F^B9 = B6, 0B^DE = D5,
//   so crc ^ K = 0x3536B6D5, bytes [D5 B6 36 35] -> [B6 36 35 D5] = 0xD53536B6.
// - crc 0xFFFFFFFF: crc ^ K = 0x12354621, bytes [21 46 35 12] -> [46 35 12 21] = 0x21123546.
TEST(HighState, ScrambledCrcIsTheSdksTransformOnKnownVectors) {
    struct Vector {
        uint32_t crc, stored;
    };
    for (const Vector& v : {Vector{0x00000000u, 0xdeedcab9u}, Vector{0x7f8a10a2u, 0x7c9240a9u},
                            Vector{0xd8fc0f0bu, 0xd53536b6u}, Vector{0xffffffffu, 0x21123546u}}) {
        EXPECT_EQ(ScrambleCrc(v.crc), v.stored) << std::hex << v.crc;
        EXPECT_EQ(UnscrambleCrc(v.stored), v.crc) << std::hex << v.crc;
    }
    // As bytes on the wire: a HighState with the scrambled form stores [A9 40 92 7C] for the
    // reference CRC 0x7F8A10A2.
    std::array<uint8_t, kHighStateSize> bytes{};
    HighState s;
    s.head = kFrameHead;
    s.level_flag = kHighLevel;
    s.bms.soc = 87;
    s.position = {1.5f, 0.f, 0.f};
    EXPECT_EQ(SerializeHighState(s, bytes, CrcForm::kScrambled), 0x7c9240a9u);
    const std::array<uint8_t, 4> wire{0xa9, 0x40, 0x92, 0x7c};
    EXPECT_TRUE(std::equal(wire.begin(), wire.end(), bytes.begin() + layout::hs::kCrc));
    EXPECT_STREQ(ToString(CrcForm::kScrambled), "scrambled");
    EXPECT_STREQ(ToString(CrcForm::kPlain), "plain");
}

// Both forms are accepted and say which one matched; either with one bit flipped anywhere in
// the covered bytes or in the CRC itself is rejected.
TEST(HighState, AcceptsPlainAndScrambledCrcAndRejectsEitherWithAFlippedBit) {
    const HighState s = MakeState();
    for (const CrcForm form : {CrcForm::kPlain, CrcForm::kScrambled}) {
        std::array<uint8_t, kHighStateSize> bytes{};
        SerializeHighState(s, bytes, form);
        HighState parsed;
        CrcForm seen = form == CrcForm::kPlain ? CrcForm::kScrambled : CrcForm::kPlain;
        ASSERT_EQ(ParseHighState(bytes, parsed, &seen), ParseResult::kOk) << ToString(form);
        EXPECT_EQ(seen, form);
        EXPECT_TRUE(parsed.motor_state == s.motor_state && parsed.position == s.position);
        for (size_t i = layout::kFrameReserve; i < kHighStateSize; ++i) {
            if (i >= layout::hs::kCrcCoveredBytes && i < layout::hs::kCrc) continue;
            for (int bit = 0; bit < 8; bit += 3) {
                auto damaged = bytes;
                damaged[i] ^= static_cast<uint8_t>(1u << bit);
                ASSERT_EQ(ParseHighState(damaged, parsed), ParseResult::kBadCrc)
                    << ToString(form) << " byte " << i << " bit " << bit;
            }
        }
    }
}

// Head and levelFlag are checked before the CRC, as the SDK's receive path does, each with its
// own result, and such a datagram is not decoded at all.
TEST(HighState, WrongHeadOrLevelFlagIsRejectedByReasonAndNotDecoded) {
    HighState s = MakeState();
    for (const auto& [head, level, expected] :
         {std::tuple{std::array<uint8_t, 2>{0xef, 0xfe}, kHighLevel, ParseResult::kBadHead},
          std::tuple{std::array<uint8_t, 2>{0xfe, 0x00}, kHighLevel, ParseResult::kBadHead},
          std::tuple{kFrameHead, kLowLevel, ParseResult::kBadLevelFlag},
          std::tuple{kFrameHead, uint8_t{0x00}, ParseResult::kBadLevelFlag}}) {
        s.head = head;
        s.level_flag = level;
        std::array<uint8_t, kHighStateSize> bytes{};
        SerializeHighState(s, bytes, CrcForm::kScrambled);  // the CRC is right for these bytes
        HighState untouched;
        untouched.mode = 99;
        EXPECT_EQ(ParseHighState(bytes, untouched), expected);
        EXPECT_EQ(untouched.mode, 99) << "a rejected frame was decoded";
        EXPECT_EQ(untouched.head, (std::array<uint8_t, 2>{}));
    }
    EXPECT_STREQ(ToString(ParseResult::kBadHead), "bad head");
    EXPECT_STREQ(ToString(ParseResult::kBadLevelFlag), "bad levelFlag");
}

TEST(HighCmd, IdleCommandIsValidAndCommandsNoMotion) {
    const HighCmd cmd = MakeIdleHighCmd();
    std::array<uint8_t, kHighCmdSize> bytes{};
    const uint32_t crc = SerializeHighCmd(cmd, bytes);
    EXPECT_EQ(crc, 0xd8fc0f0bu);  // Python reference: FE EF EE then zeros, first 124 bytes
    EXPECT_EQ(bytes[0], 0xfe);
    EXPECT_EQ(bytes[1], 0xef);
    EXPECT_EQ(bytes[2], kHighLevel);
    EXPECT_EQ(bytes[layout::hc::kMode], 0);
    for (size_t i = 3; i < layout::hc::kCrc; ++i) EXPECT_EQ(bytes[i], 0) << i;
    HighCmd parsed;
    ASSERT_EQ(ParseHighCmd(bytes, parsed), ParseResult::kOk);
    HighCmd expected = cmd;
    expected.crc = crc;
    EXPECT_TRUE(parsed == expected);
    bytes[layout::hc::kVelocity] = 1;
    EXPECT_EQ(ParseHighCmd(bytes, parsed), ParseResult::kBadCrc);
    EXPECT_EQ(ParseHighCmd(std::span<const uint8_t>(bytes).first(128), parsed),
              ParseResult::kWrongSize);
}

TEST(HighCmd, ParseOfSerializeIsIdentity) {
    HighCmd c;
    c.head = kHighCmdHead;
    c.level_flag = kHighLevel;
    c.frame_reserve = 9;
    c.sn = {1, 2};
    c.version = {3, 4};
    c.band_width = 5;
    c.mode = 2;
    c.gait_type = 1;
    c.speed_level = 1;
    c.foot_raise_height = 0.01f;
    c.body_height = -0.02f;
    c.position = {1.f, 2.f};
    c.euler = {0.1f, 0.2f, 0.3f};
    c.velocity = {0.4f, -0.5f};
    c.yaw_speed = 0.6f;
    c.bms_off = 0xa5;
    c.bms_reserve = {7, 8, 9};
    c.led = {Led{1, 2, 3}, Led{4, 5, 6}, Led{7, 8, 9}, Led{10, 11, 12}};
    for (size_t i = 0; i < c.wireless_remote.size(); ++i) {
        c.wireless_remote[i] = static_cast<uint8_t>(i + 1);
    }
    c.reserve = 77;
    std::array<uint8_t, kHighCmdSize> bytes{};
    c.crc = SerializeHighCmd(c, bytes);
    HighCmd parsed;
    ASSERT_EQ(ParseHighCmd(bytes, parsed), ParseResult::kOk);
    EXPECT_TRUE(parsed == c);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::go1_bridge
