// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Unitree Go1 high-level UDP messages: HighState (the robot's state, 1087 bytes) and HighCmd (the
// request a client sends, 129 bytes), as unitree_legged_sdk's go1 branch defines them in
// include/unitree_legged_sdk/comm.h: `#pragma pack(1)` structs, little-endian, a CRC-32 in the
// last 4 bytes. Our own code from the header's facts (see README.md, "HighState facts"): every
// offset below is derived from the field sizes, and static_asserts pin the totals.
//
// The CRC is Unitree's crc32_core: CRC-32 with polynomial 0x04C11DB7, initial value 0xFFFFFFFF,
// no reflection, no final xor, fed with 32-bit little-endian words most significant bit first
// (so it equals CRC-32/MPEG-2 over each word's bytes in reversed order). The SDK feeds it
// (sizeof(struct) >> 2) - 1 words: for HighState the first 1080 bytes (the last 3 bytes of
// `reserve` are not covered), for HighCmd the first 124 bytes. The CRC is stored little-endian in
// the last 4 bytes.
//
// Parsing and serialising neither allocate nor throw.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace bimslam::go1 {

inline constexpr uint8_t kHighLevel = 0xee;  // levelFlag HIGHLEVEL (comm.h)
inline constexpr uint8_t kLowLevel = 0xff;   // levelFlag LOWLEVEL (comm.h); never sent here
// The frame head of both messages. Not in comm.h (the library fills it); taken from captures of
// the SDK as reverse-engineered by free-dog-sdk (ucl/highCmd.py); the SDK's receive path checks
// it on HighState (drivers/go1/README.md, "What the SDK checks").
inline constexpr std::array<uint8_t, 2> kFrameHead{0xfe, 0xef};
inline constexpr std::array<uint8_t, 2> kHighCmdHead = kFrameHead;

// ------------------------------------------------------------------------------------------------
// Unitree's CRC.

// crc32_core over floor(bytes.size() / 4) little-endian 32-bit words.
uint32_t UnitreeCrc32(std::span<const uint8_t> bytes);

// How the CRC word is stored. kPlain: the CRC-32 itself. kScrambled: the SDK's encryptCRC,
// rotr32(crc ^ 0xEDCAB9DE, 8); as bytes, [b, c, d, a] where [a, b, c, d] are the little-endian
// bytes of crc ^ 0xEDCAB9DE (free-dog-sdk's ucl/common.py encryptCrc is the same transform).
enum class CrcForm : uint8_t { kPlain, kScrambled };
const char* ToString(CrcForm form);
inline constexpr uint32_t kCrcScrambleKey = 0xedcab9de;
uint32_t ScrambleCrc(uint32_t crc);
uint32_t UnscrambleCrc(uint32_t stored);  // ScrambleCrc's inverse (the SDK's decryptCRC)

// ------------------------------------------------------------------------------------------------
// Field sizes (packed) and the offsets derived from them.

namespace layout {

inline constexpr size_t kImuSize = 4 * 4 + 3 * 4 + 3 * 4 + 3 * 4 + 1;            // 53
inline constexpr size_t kMotorStateSize = 1 + 7 * 4 + 1 + 2 * 4;                 // 38
inline constexpr size_t kBmsStateSize = 1 + 1 + 1 + 1 + 4 + 2 + 2 + 2 + 10 * 2;  // 34
inline constexpr size_t kCartesianSize = 3 * 4;                                  // 12
inline constexpr size_t kBmsCmdSize = 1 + 3;                                     // 4
inline constexpr size_t kLedSize = 3;                                            // 3
inline constexpr int kMotors = 20;
inline constexpr int kLegs = 4;
inline constexpr size_t kWirelessRemoteSize = 40;

// The header common to HighState and HighCmd.
inline constexpr size_t kHead = 0;                       // uint8_t[2]
inline constexpr size_t kLevelFlag = kHead + 2;          // uint8_t
inline constexpr size_t kFrameReserve = kLevelFlag + 1;  // uint8_t
inline constexpr size_t kSn = kFrameReserve + 1;         // uint32_t[2]
inline constexpr size_t kVersion = kSn + 8;              // uint32_t[2]
inline constexpr size_t kBandWidth = kVersion + 8;       // uint16_t
inline constexpr size_t kHeaderEnd = kBandWidth + 2;

// Inside IMU.
inline constexpr size_t kImuQuaternion = 0;                      // float[4] w, x, y, z
inline constexpr size_t kImuGyroscope = kImuQuaternion + 16;     // float[3] rad/s
inline constexpr size_t kImuAccelerometer = kImuGyroscope + 12;  // float[3] m/s^2
inline constexpr size_t kImuRpy = kImuAccelerometer + 12;        // float[3] rad
inline constexpr size_t kImuTemperature = kImuRpy + 12;          // int8_t degC
static_assert(kImuTemperature + 1 == kImuSize);

// HighState.
namespace hs {
inline constexpr size_t kImu = kHeaderEnd;
inline constexpr size_t kMotorState = kImu + kImuSize;  // MotorState[20]
inline constexpr size_t kBms = kMotorState + kMotors * kMotorStateSize;
inline constexpr size_t kFootForce = kBms + kBmsStateSize;         // int16_t[4]
inline constexpr size_t kFootForceEst = kFootForce + 4 * 2;        // int16_t[4]
inline constexpr size_t kMode = kFootForceEst + 4 * 2;             // uint8_t
inline constexpr size_t kProgress = kMode + 1;                     // float
inline constexpr size_t kGaitType = kProgress + 4;                 // uint8_t
inline constexpr size_t kFootRaiseHeight = kGaitType + 1;          // float
inline constexpr size_t kPosition = kFootRaiseHeight + 4;          // float[3]
inline constexpr size_t kBodyHeight = kPosition + 12;              // float
inline constexpr size_t kVelocity = kBodyHeight + 4;               // float[3]
inline constexpr size_t kYawSpeed = kVelocity + 12;                // float
inline constexpr size_t kRangeObstacle = kYawSpeed + 4;            // float[4]
inline constexpr size_t kFootPosition2Body = kRangeObstacle + 16;  // Cartesian[4]
inline constexpr size_t kFootSpeed2Body = kFootPosition2Body + kLegs * kCartesianSize;
inline constexpr size_t kWirelessRemote = kFootSpeed2Body + kLegs * kCartesianSize;
inline constexpr size_t kReserve = kWirelessRemote + kWirelessRemoteSize;  // uint32_t
inline constexpr size_t kCrc = kReserve + 4;                               // uint32_t
inline constexpr size_t kSize = kCrc + 4;
// crc32_core(ptr, (sizeof(HighState) >> 2) - 1): whole words before the CRC's word.
inline constexpr size_t kCrcCoveredBytes = ((kSize >> 2) - 1) * 4;
}  // namespace hs
static_assert(hs::kSize == 1087, "HighState is 1087 bytes in the go1 SDK");
static_assert(hs::kImu == 22 && hs::kBms == 835 && hs::kFootForce == 869 && hs::kMode == 885 &&
              hs::kPosition == 895 && hs::kVelocity == 911 && hs::kYawSpeed == 923 &&
              hs::kWirelessRemote == 1039 && hs::kCrc == 1083);
static_assert(hs::kCrcCoveredBytes == 1080);

// HighCmd.
namespace hc {
inline constexpr size_t kMode = kHeaderEnd;                  // uint8_t
inline constexpr size_t kGaitType = kMode + 1;               // uint8_t
inline constexpr size_t kSpeedLevel = kGaitType + 1;         // uint8_t
inline constexpr size_t kFootRaiseHeight = kSpeedLevel + 1;  // float
inline constexpr size_t kBodyHeight = kFootRaiseHeight + 4;  // float
inline constexpr size_t kPosition = kBodyHeight + 4;         // float[2]
inline constexpr size_t kEuler = kPosition + 8;              // float[3]
inline constexpr size_t kVelocity = kEuler + 12;             // float[2]
inline constexpr size_t kYawSpeed = kVelocity + 8;           // float
inline constexpr size_t kBms = kYawSpeed + 4;                // BmsCmd
inline constexpr size_t kLed = kBms + kBmsCmdSize;           // LED[4]
inline constexpr size_t kWirelessRemote = kLed + kLegs * kLedSize;
inline constexpr size_t kReserve = kWirelessRemote + kWirelessRemoteSize;
inline constexpr size_t kCrc = kReserve + 4;
inline constexpr size_t kSize = kCrc + 4;
inline constexpr size_t kCrcCoveredBytes = ((kSize >> 2) - 1) * 4;
}  // namespace hc
static_assert(hc::kSize == 129, "HighCmd is 129 bytes in the go1 SDK");
static_assert(hc::kCrcCoveredBytes == 124);

}  // namespace layout

inline constexpr size_t kHighStateSize = layout::hs::kSize;
inline constexpr size_t kHighCmdSize = layout::hc::kSize;

// ------------------------------------------------------------------------------------------------
// The messages as plain structs (field names as in comm.h).

struct Imu {
    std::array<float, 4> quaternion{};     // w, x, y, z (normalised by the robot)
    std::array<float, 3> gyroscope{};      // rad/s, raw
    std::array<float, 3> accelerometer{};  // m/s^2, raw
    std::array<float, 3> rpy{};            // rad
    int8_t temperature = 0;                // degC
    bool operator==(const Imu&) const = default;
};

struct MotorState {
    uint8_t mode = 0;
    float q = 0, dq = 0, ddq = 0, tau_est = 0, q_raw = 0, dq_raw = 0, ddq_raw = 0;
    int8_t temperature = 0;
    std::array<uint32_t, 2> reserve{};
    bool operator==(const MotorState&) const = default;
};

struct BmsState {
    uint8_t version_h = 0, version_l = 0, bms_status = 0;
    uint8_t soc = 0;      // %
    int32_t current = 0;  // mA
    uint16_t cycle = 0;
    std::array<int8_t, 2> bq_ntc{};       // degC
    std::array<int8_t, 2> mcu_ntc{};      // degC
    std::array<uint16_t, 10> cell_vol{};  // mV
    bool operator==(const BmsState&) const = default;
};

struct Cartesian {
    float x = 0, y = 0, z = 0;
    bool operator==(const Cartesian&) const = default;
};

struct HighState {
    std::array<uint8_t, 2> head{};
    uint8_t level_flag = 0;
    uint8_t frame_reserve = 0;
    std::array<uint32_t, 2> sn{};
    std::array<uint32_t, 2> version{};
    uint16_t band_width = 0;
    Imu imu;
    std::array<MotorState, layout::kMotors> motor_state{};
    BmsState bms;
    std::array<int16_t, 4> foot_force{};      // raw; legs FR, FL, RR, RL
    std::array<int16_t, 4> foot_force_est{};  // raw
    uint8_t mode = 0;
    float progress = 0;
    uint8_t gait_type = 0;
    float foot_raise_height = 0;      // m
    std::array<float, 3> position{};  // m, Unitree's drifting odometry
    float body_height = 0;            // m
    std::array<float, 3> velocity{};  // m/s, body frame
    float yaw_speed = 0;              // rad/s
    std::array<float, 4> range_obstacle{};
    std::array<Cartesian, 4> foot_position_2_body{};
    std::array<Cartesian, 4> foot_speed_2_body{};
    std::array<uint8_t, 40> wireless_remote{};
    uint32_t reserve = 0;
    uint32_t crc = 0;  // as received (ParseHighState) or as written (SerializeHighState)
    bool operator==(const HighState&) const = default;
};

struct Led {
    uint8_t r = 0, g = 0, b = 0;
    bool operator==(const Led&) const = default;
};

struct HighCmd {
    std::array<uint8_t, 2> head{};
    uint8_t level_flag = 0;
    uint8_t frame_reserve = 0;
    std::array<uint32_t, 2> sn{};
    std::array<uint32_t, 2> version{};
    uint16_t band_width = 0;
    uint8_t mode = 0;  // 0 idle (default stand); anything else moves the robot
    uint8_t gait_type = 0;
    uint8_t speed_level = 0;
    float foot_raise_height = 0;
    float body_height = 0;
    std::array<float, 2> position{};
    std::array<float, 3> euler{};
    std::array<float, 2> velocity{};
    float yaw_speed = 0;
    uint8_t bms_off = 0;
    std::array<uint8_t, 3> bms_reserve{};
    std::array<Led, 4> led{};
    std::array<uint8_t, 40> wireless_remote{};
    uint32_t reserve = 0;
    uint32_t crc = 0;
    bool operator==(const HighCmd&) const = default;
};

// ------------------------------------------------------------------------------------------------
// Parsing and serialising.

// The checks in the order they are made; the first that fails is the result.
enum class ParseResult : uint8_t {
    kOk,
    kWrongSize,     // the datagram is not exactly the message's size
    kBadHead,       // HighState: head is not 0xFE 0xEF
    kBadLevelFlag,  // HighState: levelFlag is not HIGHLEVEL (0xEE)
    kBadCrc,        // the stored CRC matches neither form (the struct is still filled)
};
const char* ToString(ParseResult result);

// Fills `out` from a datagram whose size, head and levelFlag are right, and says in `crc_form`
// (when given) which form of the CRC matched. kWrongSize, kBadHead and kBadLevelFlag leave `out`
// untouched; kBadCrc fills it (for --no-crc-check diagnosis) but the caller must not trust it.
ParseResult ParseHighState(std::span<const uint8_t> bytes, HighState& out,
                           CrcForm* crc_form = nullptr);
// Writes every field, computes the CRC, stores it in the last 4 bytes in `form` and returns the
// word stored (the `crc` member of `state` is ignored).
uint32_t SerializeHighState(const HighState& state, std::span<uint8_t, kHighStateSize> out,
                            CrcForm form = CrcForm::kPlain);

// HighCmd: size and plain CRC only (the bridge sends it; tests and fake Go1s read it).
ParseResult ParseHighCmd(std::span<const uint8_t> bytes, HighCmd& out);
uint32_t SerializeHighCmd(const HighCmd& cmd, std::span<uint8_t, kHighCmdSize> out);

// The only request the bridge sends: head 0xFE 0xEF, levelFlag HIGHLEVEL, mode 0 (idle), every
// motion field zero. It asks for HighState and commands no motion.
HighCmd MakeIdleHighCmd();

}  // namespace bimslam::go1
