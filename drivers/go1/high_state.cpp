// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/go1/high_state.hpp"

#include <bit>

namespace bimslam::go1 {
namespace {

// Little-endian field access at fixed offsets, independent of the host's byte order.
class Writer {
public:
    explicit Writer(std::span<uint8_t> out) : out_(out) {}

    void U8(size_t at, uint8_t v) { out_[at] = v; }
    void I8(size_t at, int8_t v) { out_[at] = static_cast<uint8_t>(v); }
    void U16(size_t at, uint16_t v) {
        out_[at] = static_cast<uint8_t>(v);
        out_[at + 1] = static_cast<uint8_t>(v >> 8);
    }
    void I16(size_t at, int16_t v) { U16(at, static_cast<uint16_t>(v)); }
    void U32(size_t at, uint32_t v) {
        for (size_t i = 0; i < 4; ++i) out_[at + i] = static_cast<uint8_t>(v >> (8 * i));
    }
    void I32(size_t at, int32_t v) { U32(at, static_cast<uint32_t>(v)); }
    void F32(size_t at, float v) { U32(at, std::bit_cast<uint32_t>(v)); }
    template <size_t N>
    void Bytes(size_t at, const std::array<uint8_t, N>& v) {
        for (size_t i = 0; i < N; ++i) out_[at + i] = v[i];
    }
    template <size_t N>
    void F32s(size_t at, const std::array<float, N>& v) {
        for (size_t i = 0; i < N; ++i) F32(at + 4 * i, v[i]);
    }
    template <size_t N>
    void U32s(size_t at, const std::array<uint32_t, N>& v) {
        for (size_t i = 0; i < N; ++i) U32(at + 4 * i, v[i]);
    }

private:
    std::span<uint8_t> out_;
};

class Reader {
public:
    explicit Reader(std::span<const uint8_t> in) : in_(in) {}

    uint8_t U8(size_t at) const { return in_[at]; }
    int8_t I8(size_t at) const { return static_cast<int8_t>(in_[at]); }
    uint16_t U16(size_t at) const {
        return static_cast<uint16_t>(in_[at] | (static_cast<unsigned>(in_[at + 1]) << 8));
    }
    int16_t I16(size_t at) const { return static_cast<int16_t>(U16(at)); }
    uint32_t U32(size_t at) const {
        uint32_t v = 0;
        for (size_t i = 0; i < 4; ++i) v |= static_cast<uint32_t>(in_[at + i]) << (8 * i);
        return v;
    }
    int32_t I32(size_t at) const { return static_cast<int32_t>(U32(at)); }
    float F32(size_t at) const { return std::bit_cast<float>(U32(at)); }
    template <size_t N>
    void Bytes(size_t at, std::array<uint8_t, N>& v) const {
        for (size_t i = 0; i < N; ++i) v[i] = in_[at + i];
    }
    template <size_t N>
    void F32s(size_t at, std::array<float, N>& v) const {
        for (size_t i = 0; i < N; ++i) v[i] = F32(at + 4 * i);
    }
    template <size_t N>
    void U32s(size_t at, std::array<uint32_t, N>& v) const {
        for (size_t i = 0; i < N; ++i) v[i] = U32(at + 4 * i);
    }

private:
    std::span<const uint8_t> in_;
};

// The header shared by both messages.
template <class Msg>
void WriteHeader(Writer& w, const Msg& m) {
    using namespace layout;
    w.Bytes(kHead, m.head);
    w.U8(kLevelFlag, m.level_flag);
    w.U8(kFrameReserve, m.frame_reserve);
    w.U32s(kSn, m.sn);
    w.U32s(kVersion, m.version);
    w.U16(kBandWidth, m.band_width);
}

template <class Msg>
void ReadHeader(const Reader& r, Msg& m) {
    using namespace layout;
    r.Bytes(kHead, m.head);
    m.level_flag = r.U8(kLevelFlag);
    m.frame_reserve = r.U8(kFrameReserve);
    r.U32s(kSn, m.sn);
    r.U32s(kVersion, m.version);
    m.band_width = r.U16(kBandWidth);
}

void WriteCartesian(Writer& w, size_t at, const Cartesian& c) {
    w.F32(at, c.x);
    w.F32(at + 4, c.y);
    w.F32(at + 8, c.z);
}

Cartesian ReadCartesian(const Reader& r, size_t at) {
    return Cartesian{r.F32(at), r.F32(at + 4), r.F32(at + 8)};
}

// Offsets inside MotorState and BmsState.
namespace ms {
constexpr size_t kMode = 0, kQ = 1, kDq = 5, kDdq = 9, kTauEst = 13, kQRaw = 17, kDqRaw = 21,
                 kDdqRaw = 25, kTemperature = 29, kReserve = 30;
static_assert(kReserve + 8 == layout::kMotorStateSize);
}  // namespace ms
namespace bms {
constexpr size_t kVersionH = 0, kVersionL = 1, kStatus = 2, kSoc = 3, kCurrent = 4, kCycle = 8,
                 kBqNtc = 10, kMcuNtc = 12, kCellVol = 14;
static_assert(kCellVol + 20 == layout::kBmsStateSize);
}  // namespace bms

}  // namespace

uint32_t UnitreeCrc32(std::span<const uint8_t> bytes) {
    constexpr uint32_t kPolynomial = 0x04c11db7;
    uint32_t crc = 0xffffffff;
    const size_t words = bytes.size() / 4;
    for (size_t i = 0; i < words; ++i) {
        const uint8_t* p = bytes.data() + 4 * i;
        const uint32_t word = static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) |
                              (static_cast<uint32_t>(p[2]) << 16) |
                              (static_cast<uint32_t>(p[3]) << 24);
        // Most significant bit first: shift the register, feed back the bit that fell out xor
        // the data bit.
        for (int bit = 31; bit >= 0; --bit) {
            const uint32_t feedback = (crc >> 31) ^ ((word >> bit) & 1u);
            crc <<= 1;
            if (feedback) crc ^= kPolynomial;
        }
    }
    return crc;
}

const char* ToString(CrcForm form) {
    switch (form) {
        case CrcForm::kPlain:
            return "plain";
        case CrcForm::kScrambled:
            return "scrambled";
    }
    return "?";
}

uint32_t ScrambleCrc(uint32_t crc) { return std::rotr(crc ^ kCrcScrambleKey, 8); }

uint32_t UnscrambleCrc(uint32_t stored) { return std::rotl(stored, 8) ^ kCrcScrambleKey; }

const char* ToString(ParseResult result) {
    switch (result) {
        case ParseResult::kOk:
            return "ok";
        case ParseResult::kWrongSize:
            return "wrong size";
        case ParseResult::kBadHead:
            return "bad head";
        case ParseResult::kBadLevelFlag:
            return "bad levelFlag";
        case ParseResult::kBadCrc:
            return "bad CRC";
    }
    return "?";
}

uint32_t SerializeHighState(const HighState& s, std::span<uint8_t, kHighStateSize> out,
                            CrcForm form) {
    using namespace layout;
    using namespace layout::hs;
    Writer w(out);
    WriteHeader(w, s);
    w.F32s(kImu + kImuQuaternion, s.imu.quaternion);
    w.F32s(kImu + kImuGyroscope, s.imu.gyroscope);
    w.F32s(kImu + kImuAccelerometer, s.imu.accelerometer);
    w.F32s(kImu + kImuRpy, s.imu.rpy);
    w.I8(kImu + kImuTemperature, s.imu.temperature);
    for (size_t i = 0; i < s.motor_state.size(); ++i) {
        const MotorState& m = s.motor_state[i];
        const size_t at = kMotorState + i * kMotorStateSize;
        w.U8(at + ms::kMode, m.mode);
        w.F32(at + ms::kQ, m.q);
        w.F32(at + ms::kDq, m.dq);
        w.F32(at + ms::kDdq, m.ddq);
        w.F32(at + ms::kTauEst, m.tau_est);
        w.F32(at + ms::kQRaw, m.q_raw);
        w.F32(at + ms::kDqRaw, m.dq_raw);
        w.F32(at + ms::kDdqRaw, m.ddq_raw);
        w.I8(at + ms::kTemperature, m.temperature);
        w.U32s(at + ms::kReserve, m.reserve);
    }
    w.U8(kBms + bms::kVersionH, s.bms.version_h);
    w.U8(kBms + bms::kVersionL, s.bms.version_l);
    w.U8(kBms + bms::kStatus, s.bms.bms_status);
    w.U8(kBms + bms::kSoc, s.bms.soc);
    w.I32(kBms + bms::kCurrent, s.bms.current);
    w.U16(kBms + bms::kCycle, s.bms.cycle);
    for (size_t i = 0; i < 2; ++i) {
        w.I8(kBms + bms::kBqNtc + i, s.bms.bq_ntc[i]);
        w.I8(kBms + bms::kMcuNtc + i, s.bms.mcu_ntc[i]);
    }
    for (size_t i = 0; i < s.bms.cell_vol.size(); ++i) {
        w.U16(kBms + bms::kCellVol + 2 * i, s.bms.cell_vol[i]);
    }
    for (size_t i = 0; i < 4; ++i) {
        w.I16(kFootForce + 2 * i, s.foot_force[i]);
        w.I16(kFootForceEst + 2 * i, s.foot_force_est[i]);
    }
    w.U8(kMode, s.mode);
    w.F32(kProgress, s.progress);
    w.U8(kGaitType, s.gait_type);
    w.F32(kFootRaiseHeight, s.foot_raise_height);
    w.F32s(kPosition, s.position);
    w.F32(kBodyHeight, s.body_height);
    w.F32s(kVelocity, s.velocity);
    w.F32(kYawSpeed, s.yaw_speed);
    w.F32s(kRangeObstacle, s.range_obstacle);
    for (size_t i = 0; i < 4; ++i) {
        WriteCartesian(w, kFootPosition2Body + i * kCartesianSize, s.foot_position_2_body[i]);
        WriteCartesian(w, kFootSpeed2Body + i * kCartesianSize, s.foot_speed_2_body[i]);
    }
    w.Bytes(kWirelessRemote, s.wireless_remote);
    w.U32(kReserve, s.reserve);
    const uint32_t crc = UnitreeCrc32(std::span<const uint8_t>(out.data(), kCrcCoveredBytes));
    const uint32_t stored = form == CrcForm::kScrambled ? ScrambleCrc(crc) : crc;
    w.U32(kCrc, stored);
    return stored;
}

ParseResult ParseHighState(std::span<const uint8_t> bytes, HighState& s, CrcForm* crc_form) {
    using namespace layout;
    using namespace layout::hs;
    if (bytes.size() != kHighStateSize) return ParseResult::kWrongSize;
    const Reader r(bytes);
    // The frame checks come before any field is decoded: a datagram that is not a high-level
    // HighState is never read as one.
    if (r.U8(kHead) != kFrameHead[0] || r.U8(kHead + 1) != kFrameHead[1]) {
        return ParseResult::kBadHead;
    }
    if (r.U8(kLevelFlag) != kHighLevel) return ParseResult::kBadLevelFlag;
    ReadHeader(r, s);
    r.F32s(kImu + kImuQuaternion, s.imu.quaternion);
    r.F32s(kImu + kImuGyroscope, s.imu.gyroscope);
    r.F32s(kImu + kImuAccelerometer, s.imu.accelerometer);
    r.F32s(kImu + kImuRpy, s.imu.rpy);
    s.imu.temperature = r.I8(kImu + kImuTemperature);
    for (size_t i = 0; i < s.motor_state.size(); ++i) {
        MotorState& m = s.motor_state[i];
        const size_t at = kMotorState + i * kMotorStateSize;
        m.mode = r.U8(at + ms::kMode);
        m.q = r.F32(at + ms::kQ);
        m.dq = r.F32(at + ms::kDq);
        m.ddq = r.F32(at + ms::kDdq);
        m.tau_est = r.F32(at + ms::kTauEst);
        m.q_raw = r.F32(at + ms::kQRaw);
        m.dq_raw = r.F32(at + ms::kDqRaw);
        m.ddq_raw = r.F32(at + ms::kDdqRaw);
        m.temperature = r.I8(at + ms::kTemperature);
        r.U32s(at + ms::kReserve, m.reserve);
    }
    s.bms.version_h = r.U8(kBms + bms::kVersionH);
    s.bms.version_l = r.U8(kBms + bms::kVersionL);
    s.bms.bms_status = r.U8(kBms + bms::kStatus);
    s.bms.soc = r.U8(kBms + bms::kSoc);
    s.bms.current = r.I32(kBms + bms::kCurrent);
    s.bms.cycle = r.U16(kBms + bms::kCycle);
    for (size_t i = 0; i < 2; ++i) {
        s.bms.bq_ntc[i] = r.I8(kBms + bms::kBqNtc + i);
        s.bms.mcu_ntc[i] = r.I8(kBms + bms::kMcuNtc + i);
    }
    for (size_t i = 0; i < s.bms.cell_vol.size(); ++i) {
        s.bms.cell_vol[i] = r.U16(kBms + bms::kCellVol + 2 * i);
    }
    for (size_t i = 0; i < 4; ++i) {
        s.foot_force[i] = r.I16(kFootForce + 2 * i);
        s.foot_force_est[i] = r.I16(kFootForceEst + 2 * i);
    }
    s.mode = r.U8(kMode);
    s.progress = r.F32(kProgress);
    s.gait_type = r.U8(kGaitType);
    s.foot_raise_height = r.F32(kFootRaiseHeight);
    r.F32s(kPosition, s.position);
    s.body_height = r.F32(kBodyHeight);
    r.F32s(kVelocity, s.velocity);
    s.yaw_speed = r.F32(kYawSpeed);
    r.F32s(kRangeObstacle, s.range_obstacle);
    for (size_t i = 0; i < 4; ++i) {
        s.foot_position_2_body[i] = ReadCartesian(r, kFootPosition2Body + i * kCartesianSize);
        s.foot_speed_2_body[i] = ReadCartesian(r, kFootSpeed2Body + i * kCartesianSize);
    }
    r.Bytes(kWirelessRemote, s.wireless_remote);
    s.reserve = r.U32(kReserve);
    s.crc = r.U32(kCrc);
    // Either form, as the SDK's developer mode accepts both (README, "What the SDK checks").
    const uint32_t computed = UnitreeCrc32(bytes.first(kCrcCoveredBytes));
    if (computed == s.crc) {
        if (crc_form != nullptr) *crc_form = CrcForm::kPlain;
        return ParseResult::kOk;
    }
    if (computed == UnscrambleCrc(s.crc)) {
        if (crc_form != nullptr) *crc_form = CrcForm::kScrambled;
        return ParseResult::kOk;
    }
    return ParseResult::kBadCrc;
}

uint32_t SerializeHighCmd(const HighCmd& c, std::span<uint8_t, kHighCmdSize> out) {
    using namespace layout;
    using namespace layout::hc;
    Writer w(out);
    WriteHeader(w, c);
    w.U8(kMode, c.mode);
    w.U8(kGaitType, c.gait_type);
    w.U8(kSpeedLevel, c.speed_level);
    w.F32(kFootRaiseHeight, c.foot_raise_height);
    w.F32(kBodyHeight, c.body_height);
    w.F32s(kPosition, c.position);
    w.F32s(kEuler, c.euler);
    w.F32s(kVelocity, c.velocity);
    w.F32(kYawSpeed, c.yaw_speed);
    w.U8(kBms, c.bms_off);
    w.Bytes(kBms + 1, c.bms_reserve);
    for (size_t i = 0; i < c.led.size(); ++i) {
        w.U8(kLed + i * kLedSize, c.led[i].r);
        w.U8(kLed + i * kLedSize + 1, c.led[i].g);
        w.U8(kLed + i * kLedSize + 2, c.led[i].b);
    }
    w.Bytes(kWirelessRemote, c.wireless_remote);
    w.U32(kReserve, c.reserve);
    const uint32_t crc = UnitreeCrc32(std::span<const uint8_t>(out.data(), kCrcCoveredBytes));
    w.U32(kCrc, crc);
    return crc;
}

ParseResult ParseHighCmd(std::span<const uint8_t> bytes, HighCmd& c) {
    using namespace layout;
    using namespace layout::hc;
    if (bytes.size() != kHighCmdSize) return ParseResult::kWrongSize;
    const Reader r(bytes);
    ReadHeader(r, c);
    c.mode = r.U8(kMode);
    c.gait_type = r.U8(kGaitType);
    c.speed_level = r.U8(kSpeedLevel);
    c.foot_raise_height = r.F32(kFootRaiseHeight);
    c.body_height = r.F32(kBodyHeight);
    r.F32s(kPosition, c.position);
    r.F32s(kEuler, c.euler);
    r.F32s(kVelocity, c.velocity);
    c.yaw_speed = r.F32(kYawSpeed);
    c.bms_off = r.U8(kBms);
    r.Bytes(kBms + 1, c.bms_reserve);
    for (size_t i = 0; i < c.led.size(); ++i) {
        c.led[i] = Led{r.U8(kLed + i * kLedSize), r.U8(kLed + i * kLedSize + 1),
                       r.U8(kLed + i * kLedSize + 2)};
    }
    r.Bytes(kWirelessRemote, c.wireless_remote);
    c.reserve = r.U32(kReserve);
    c.crc = r.U32(kCrc);
    const uint32_t computed = UnitreeCrc32(bytes.first(kCrcCoveredBytes));
    return computed == c.crc ? ParseResult::kOk : ParseResult::kBadCrc;
}

HighCmd MakeIdleHighCmd() {
    HighCmd cmd;
    cmd.head = kHighCmdHead;
    cmd.level_flag = kHighLevel;
    cmd.mode = 0;
    cmd.gait_type = 0;
    return cmd;
}

}  // namespace bimslam::go1
