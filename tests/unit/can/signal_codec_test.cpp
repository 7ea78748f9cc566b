// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/can/signal_codec.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "algorithms/common/status.hpp"

namespace bimslam::can {
namespace {
namespace BIMSLAM_UNITY_ID {

// Bit by bit from Vector's numbering (bit b = bit b%8 of byte b/8): the reference the codec's
// byte loops and word shifts must reproduce.
uint64_t ReferenceExtract(const uint8_t* d, uint32_t start, uint32_t length, ByteOrder order) {
    uint64_t v = 0;
    uint32_t p = start;
    for (uint32_t k = 0; k < length; ++k) {
        const uint64_t bit = (d[p / 8] >> (p % 8)) & 1;
        if (order == ByteOrder::kIntel) {
            v |= bit << k;  // start bit = LSB, ascending
            ++p;
        } else {
            v |= bit << (length - 1 - k);  // start bit = MSB, sawtooth
            p = p % 8 == 0 ? p + 15 : p - 1;
        }
    }
    return v;
}

DbcSignal MakeSignal(uint32_t start, uint32_t length, ByteOrder order, bool is_signed,
                     double factor = 1, double offset = 0, double min = 0, double max = 0) {
    DbcSignal s;
    s.name = "S";
    s.start_bit = start;
    s.length = length;
    s.byte_order = order;
    s.is_signed = is_signed;
    s.factor = factor;
    s.offset = offset;
    s.minimum = min;
    s.maximum = max;
    return s;
}

using Bytes = std::array<uint8_t, 8>;

TEST(SignalCodec, CantoolsMotohawkExampleMotorola) {
    // cantools' tests/files/dbc/motohawk.dbc and its documented encodings:
    // {Temperature 250.55, AverageRadius 3.2, Enable 1} <-> c0 06 e0 00 00 00 00 00,
    // {Temperature 229.53, AverageRadius 0, Enable 0} <-> 01 00 20 00 00 00 00 00.
    const Dbc dbc = ParseDbc(
        "BO_ 496 ExampleMessage: 8 PCM1\n"
        " SG_ Enable : 7|1@0+ (1,0) [0|0] \"-\" Vector__XXX\n"
        " SG_ AverageRadius : 6|6@0+ (0.1,0) [0|5] \"m\" Vector__XXX\n"
        " SG_ Temperature : 0|12@0- (0.01,250) [229.52|270.47] \"degK\" PCM1,FOO\n",
        "motohawk.dbc");
    const MessageCodec m(dbc.messages[0]);
    const SignalCodec& enable = m[m.Index("Enable")];
    const SignalCodec& radius = m[m.Index("AverageRadius")];
    const SignalCodec& temp = m[m.Index("Temperature")];
    struct {
        double t, r, e;
        Bytes bytes;
    } cases[] = {{250.55, 3.2, 1, {0xC0, 0x06, 0xE0, 0, 0, 0, 0, 0}},
                 {229.53, 0.0, 0, {0x01, 0x00, 0x20, 0, 0, 0, 0, 0}}};
    for (const auto& c : cases) {
        Bytes d{};
        EXPECT_EQ(temp.Pack(d.data(), c.t), PackResult::kOk);
        EXPECT_EQ(radius.Pack(d.data(), c.r), PackResult::kOk);
        EXPECT_EQ(enable.Pack(d.data(), c.e), PackResult::kOk);
        EXPECT_EQ(d, c.bytes);
        EXPECT_NEAR(temp.Unpack(c.bytes.data()), c.t, 1e-9);
        EXPECT_NEAR(radius.Unpack(c.bytes.data()), c.r, 1e-9);
        EXPECT_NEAR(enable.Unpack(c.bytes.data()), c.e, 1e-9);
    }
    EXPECT_EQ(temp.first_byte(), 0u);
    EXPECT_EQ(temp.end_byte(), 3u);  // straddles bytes 0, 1 and 2
}

TEST(SignalCodec, MotorolaStartBitIsTheMsbInSawtoothNumbering) {
    const Bytes d = {0x12, 0x34, 0x56, 0x78, 0x9A, 0xBC, 0xDE, 0xF0};
    // canmatrix's example: 7|32@0- fills bytes 0..3, 39|32@0- bytes 4..7, big-endian.
    const SignalCodec s1(MakeSignal(7, 32, ByteOrder::kMotorola, true));
    const SignalCodec s2(MakeSignal(39, 32, ByteOrder::kMotorola, true));
    EXPECT_EQ(s1.Extract(d.data()), 0x12345678u);
    EXPECT_EQ(s2.Extract(d.data()), 0x9ABCDEF0u);
    EXPECT_EQ(s2.SignedRaw(s2.Extract(d.data())), int64_t{-0x65432110});
    // 7|16@0+ is a big-endian uint16 in bytes 0..1; 7|64@0+ the whole frame.
    EXPECT_EQ(SignalCodec(MakeSignal(7, 16, ByteOrder::kMotorola, false)).Extract(d.data()),
              0x1234u);
    EXPECT_EQ(SignalCodec(MakeSignal(7, 64, ByteOrder::kMotorola, false)).Extract(d.data()),
              0x123456789ABCDEF0u);
    // 2|12@0+: byte 0 bits 2..0, all of byte 1, byte 2 bit 7.
    Bytes e{};
    SignalCodec(MakeSignal(2, 12, ByteOrder::kMotorola, false)).Insert(e.data(), 0xFFF);
    EXPECT_EQ(e, (Bytes{0x07, 0xFF, 0x80, 0, 0, 0, 0, 0}));
    // 3|8@0+: high nibble in byte 0 bits 3..0, low nibble in byte 1 bits 7..4.
    const Bytes f = {0x0A, 0xB0, 0, 0, 0, 0, 0, 0};
    EXPECT_EQ(SignalCodec(MakeSignal(3, 8, ByteOrder::kMotorola, false)).Extract(f.data()), 0xABu);
}

TEST(SignalCodec, IntelStartBitIsTheLsbAscendingThroughBytes) {
    // GO1_FOOT: FOOT_Force_FR 16|12, FOOT_Force_FL 28|12.
    Bytes d{};
    SignalCodec(MakeSignal(16, 12, ByteOrder::kIntel, false)).Insert(d.data(), 0xABC);
    SignalCodec(MakeSignal(28, 12, ByteOrder::kIntel, false)).Insert(d.data(), 0x123);
    EXPECT_EQ(d, (Bytes{0, 0, 0xBC, 0x3A, 0x12, 0, 0, 0}));
    const SignalCodec all(MakeSignal(0, 64, ByteOrder::kIntel, true));
    const Bytes m1 = {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF};
    EXPECT_EQ(all.SignedRaw(all.Extract(m1.data())), -1);
    EXPECT_EQ(all.ToPhysical(all.Extract(m1.data())), -1.0);
}

TEST(SignalCodec, ByteLoopsAndWordShiftsAgreeWithTheBitwiseReference) {
    std::mt19937 rng(5);
    for (int i = 0; i < 20000; ++i) {
        const ByteOrder order = rng() % 2 ? ByteOrder::kIntel : ByteOrder::kMotorola;
        const uint32_t length = 1 + rng() % 64;
        uint32_t start;
        if (order == ByteOrder::kIntel) {
            start = rng() % (64 - length + 1);
        } else {
            // Any MSB whose sequential position leaves room for the length.
            const uint32_t msb_seq = rng() % (64 - length + 1);
            start = (msb_seq / 8) * 8 + 7 - msb_seq % 8;
        }
        const SignalCodec c(MakeSignal(start, length, order, rng() % 2));
        ASSERT_TRUE(c.fits_word());
        Bytes d;
        for (auto& b : d) b = static_cast<uint8_t>(rng());
        uint64_t word = 0;
        for (int k = 7; k >= 0; --k) word = (word << 8) | d[k];
        const uint64_t want = ReferenceExtract(d.data(), start, length, order);
        ASSERT_EQ(c.Extract(d.data()), want) << start << "|" << length;
        ASSERT_EQ(c.ExtractWord(word), want) << start << "|" << length;
        // Insert writes exactly the signal's bits.
        const uint64_t value = (uint64_t{rng()} << 32 | rng()) & c.mask();
        Bytes e = d;
        c.Insert(e.data(), value);
        ASSERT_EQ(ReferenceExtract(e.data(), start, length, order), value);
        uint64_t e_word = 0;
        for (int k = 7; k >= 0; --k) e_word = (e_word << 8) | e[k];
        ASSERT_EQ(c.InsertWord(word, value), e_word);
        c.Insert(e.data(), want);
        ASSERT_EQ(e, d);  // every other bit untouched
    }
}

// Signals that have no SNA: the spec's pattern lies within their range (flags, CRC, reserved
// fields, the full 32-bit BridgeTime).
bool ExpectNoSna(const std::string& name) {
    for (const char* part : {"_CRC", "_Valid", "Reserved", "BridgeTime", "Saturated", "ResetFlag",
                             "Contact", "UdpLinkOk", "HighStateCrcOk"}) {
        if (name.find(part) != std::string::npos) return true;
    }
    return false;
}

TEST(SignalCodec, EverySignalOfTheDbcRoundTripsAtMinMaxZeroAndSna) {
    std::mt19937 rng(9);
    size_t checked = 0, with_sna = 0;
    for (const DbcMessage& m : Go1Dbc().messages) {
        const MessageCodec codec(m);
        for (size_t i = 0; i < codec.size(); ++i) {
            const DbcSignal& s = m.signals[i];
            const SignalCodec& c = codec[i];
            SCOPED_TRACE(s.name);
            const double half_step = std::fabs(s.factor) / 2 + 1e-12;
            EXPECT_EQ(c.has_sna(), !ExpectNoSna(s.name));
            // Background bits must survive every pack.
            Bytes background;
            for (auto& b : background) b = static_cast<uint8_t>(rng());
            for (double v : {s.minimum, s.maximum, 0.0, c.min_physical(), c.max_physical()}) {
                Bytes d = background;
                ASSERT_EQ(c.Pack(d.data(), v), PackResult::kOk) << v;
                uint64_t word = 0;
                for (int k = 7; k >= 0; --k) word = (word << 8) | d[k];
                const uint64_t raw = c.Extract(d.data());
                EXPECT_EQ(c.ExtractWord(word), raw);
                EXPECT_FALSE(c.IsSna(raw)) << v;
                EXPECT_TRUE(c.InRange(raw)) << v;
                EXPECT_NEAR(c.ToPhysical(raw), v, half_step) << v;
                c.Insert(d.data(), c.Extract(background.data()));
                EXPECT_EQ(d, background);
            }
            EXPECT_NEAR(c.min_physical(), s.minimum, half_step);
            EXPECT_NEAR(c.max_physical(), s.maximum, half_step);
            if (c.has_sna()) {
                ++with_sna;
                Bytes d = background;
                EXPECT_EQ(c.Pack(d.data(), std::numeric_limits<double>::quiet_NaN()),
                          PackResult::kSna);
                const uint64_t raw = c.Extract(d.data());
                EXPECT_TRUE(c.IsSna(raw));
                EXPECT_EQ(raw, c.sna_raw());
                EXPECT_FALSE(c.InRange(raw));  // in our DBC every SNA lies outside the range
                // The spec's patterns, or GenSigSNA where given.
                const uint64_t want = s.gen_sig_sna ? *s.gen_sig_sna
                                      : s.is_signed ? uint64_t{1} << (s.length - 1)
                                                    : c.mask();
                EXPECT_EQ(raw, want);
                // A finite value never packs to the SNA pattern: it is clamped first.
                for (double v : {s.minimum - 1e6, s.maximum + 1e6}) {
                    uint64_t r = 0;
                    EXPECT_EQ(c.ToRaw(v, &r), PackResult::kClamped);
                    EXPECT_FALSE(c.IsSna(r));
                }
            }
            ++checked;
        }
    }
    EXPECT_EQ(checked, 80u);
    EXPECT_EQ(with_sna, 40u);
}

TEST(SignalCodec, SpecSnaPatterns) {
    const Dbc& dbc = Go1Dbc();
    auto codec = [&](uint32_t id, const char* name) {
        const MessageCodec m(*dbc.FindMessage(id));
        return m[m.Index(name)];
    };
    EXPECT_EQ(codec(0x112, "QUAT_X").sna_raw(), 0x8000u);          // signed 16 bit
    EXPECT_EQ(codec(0x130, "OXY_PosX").sna_raw(), 0x800000u);      // signed 24 bit (GenSigSNA)
    EXPECT_EQ(codec(0x120, "FOOT_Force_FR").sna_raw(), 0xFFFu);    // unsigned all ones
    EXPECT_EQ(codec(0x140, "STS_ImuTemp").sna_raw(), 0x80u);       // signed 8 bit
    EXPECT_EQ(codec(0x101, "BST_BodyHeight").sna_raw(), 0xFFFFu);  // unsigned 16 bit
    EXPECT_FALSE(codec(0x0F0, "SYNC_BridgeTime").has_sna());
    EXPECT_FALSE(codec(0x100, "BVEL_Valid").has_sna());
}

TEST(SignalCodec, PackRoundsClampsAndFlags) {
    const SignalCodec vx(MakeSignal(16, 16, ByteOrder::kIntel, true, 0.001, 0, -32.767, 32.767));
    uint64_t raw = 0;
    EXPECT_EQ(vx.ToRaw(1.2344, &raw), PackResult::kOk);
    EXPECT_EQ(vx.SignedRaw(raw), 1234);
    EXPECT_EQ(vx.ToRaw(-1.2346, &raw), PackResult::kOk);
    EXPECT_EQ(vx.SignedRaw(raw), -1235);
    EXPECT_EQ(vx.ToRaw(40.0, &raw), PackResult::kClamped);
    EXPECT_EQ(vx.SignedRaw(raw), 32767);
    EXPECT_EQ(vx.ToRaw(-1e300, &raw), PackResult::kClamped);
    EXPECT_EQ(vx.SignedRaw(raw), -32767);  // the range's bound, not the SNA -32768
    EXPECT_EQ(vx.ToRaw(std::numeric_limits<double>::infinity(), &raw), PackResult::kSna);
    EXPECT_EQ(raw, 0x8000u);
    // No range: the type's bounds; no SNA: a NaN packs to 0.
    const SignalCodec u8(MakeSignal(0, 8, ByteOrder::kIntel, false));
    EXPECT_FALSE(u8.has_sna());
    EXPECT_EQ(u8.ToRaw(300, &raw), PackResult::kClamped);
    EXPECT_EQ(raw, 255u);
    EXPECT_EQ(u8.ToRaw(-3, &raw), PackResult::kClamped);
    EXPECT_EQ(raw, 0u);
    EXPECT_EQ(u8.ToRaw(std::nan(""), &raw), PackResult::kNotFinite);
    // 64-bit types saturate without overflow.
    const SignalCodec u64(MakeSignal(0, 64, ByteOrder::kIntel, false));
    EXPECT_EQ(u64.ToRaw(1e30, &raw), PackResult::kClamped);
    EXPECT_EQ(raw, ~uint64_t{0});
    const SignalCodec s64(MakeSignal(0, 64, ByteOrder::kMotorola, true));
    EXPECT_EQ(s64.ToRaw(-1e30, &raw), PackResult::kClamped);
    EXPECT_EQ(s64.SignedRaw(raw), std::numeric_limits<int64_t>::min());
    EXPECT_EQ(s64.ToRaw(-12345, &raw), PackResult::kOk);
    EXPECT_EQ(s64.SignedRaw(raw), -12345);
    // A negative factor flips the range.
    const SignalCodec neg(MakeSignal(0, 8, ByteOrder::kIntel, true, -0.5, 0, -10, 10));
    EXPECT_EQ(neg.ToRaw(5, &raw), PackResult::kOk);
    EXPECT_EQ(neg.SignedRaw(raw), -10);
    EXPECT_EQ(neg.ToRaw(11, &raw), PackResult::kClamped);
    EXPECT_EQ(neg.SignedRaw(raw), -20);
    EXPECT_DOUBLE_EQ(neg.min_physical(), -10);
    EXPECT_DOUBLE_EQ(neg.max_physical(), 10);
}

TEST(SignalCodec, RefusesImpossibleSignals) {
    EXPECT_THROW(SignalCodec(MakeSignal(0, 0, ByteOrder::kIntel, false)), common::Error);
    EXPECT_THROW(SignalCodec(MakeSignal(0, 65, ByteOrder::kIntel, false)), common::Error);
    EXPECT_THROW(SignalCodec(MakeSignal(0, 8, ByteOrder::kIntel, false, 0)), common::Error);
    EXPECT_THROW(SignalCodec(MakeSignal(0, 8, ByteOrder::kIntel, false, 1, 0, -5, -1)),
                 common::Error);
    const MessageCodec m(*Go1Dbc().FindMessage(0x100));
    EXPECT_EQ(m.Index("BVEL_Vy"), 5u);  // after CRC, Counter, Valid, Reserved0, Vx
    EXPECT_EQ(m.signal_name(5), "BVEL_Vy");
    try {
        (void)m.Index("BVEL_Vz");
        ADD_FAILURE();
    } catch (const common::Error& e) {
        EXPECT_EQ(std::string(e.what()), "BO_ GO1_BODY_VEL has no signal BVEL_Vz");
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::can
