// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/las.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "algorithms/io/file_util.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::io {
namespace {
namespace BIMSLAM_UNITY_ID {
using common::Error;
using common::FileError;

template <typename T>
T At(const std::string& b, size_t offset) {
    T v;
    std::memcpy(&v, b.data() + offset, sizeof v);
    return v;
}

// Points around a building far from the origin (a georeferenced model), with every field set.
LasData Sample(size_t n) {
    LasData d;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0, 30);
    LasExtraField dist{"distance", LasType::kFloat32, "signed distance to the model, m", 1e9, {}};
    LasExtraField element{"element", LasType::kInt32, "model element index", -1, {}};
    LasExtraField views{"keyframes", LasType::kUint16, "keyframes that saw it", {}, {}};
    for (size_t i = 0; i < n; ++i) {
        d.xyz.push_back(Eigen::Vector3d(512300.25 + u(rng), 5403100.5 + u(rng), 300 + u(rng) / 10));
        d.classification.push_back(i % 3 == 0 ? kLasClassBuilding : kLasClassFirstUser + i % 4);
        d.user_data.push_back(uint8_t(i % 6));
        d.point_source_id.push_back(uint16_t(1 + i % 3));
        d.gps_time.push_back(4.8e8 + 0.1 * double(i));
        dist.values.push_back(i % 7 == 0 ? 1e9 : float(u(rng) - 15) / 100);
        element.values.push_back(i % 5 == 0 ? -1 : double(i % 1000));
        views.values.push_back(double(i % 70000 % 65536));
    }
    d.extra = {dist, element, views};
    d.file_source_id = 2;
    d.creation_day_of_year = 336;
    d.creation_year = 2026;
    return d;
}

// The header as the spec lays it out (R15 Table 3), read at its byte offsets, not by our reader.
TEST(Las, HeaderFieldsAreWhereLas14PutsThem) {
    const LasData d = Sample(1000);
    const std::string b = SerializeLas(d);
    const size_t record = 30 + 4 + 4 + 2;
    const size_t data_at = 375 + 54 + 3 * 192;
    ASSERT_EQ(b.size(), data_at + 1000 * record);
    EXPECT_EQ(b.substr(0, 4), "LASF");
    EXPECT_EQ(At<uint16_t>(b, 4), 2);     // file source id
    EXPECT_EQ(At<uint16_t>(b, 6), 0x11);  // adjusted standard GPS time, WKT bit
    EXPECT_EQ(At<uint8_t>(b, 24), 1);     // version 1.4
    EXPECT_EQ(At<uint8_t>(b, 25), 4);
    EXPECT_STREQ(b.data() + 58, "bimslam");  // generating software
    EXPECT_EQ(At<uint16_t>(b, 90), 336);
    EXPECT_EQ(At<uint16_t>(b, 92), 2026);
    EXPECT_EQ(At<uint16_t>(b, 94), 375);      // header size
    EXPECT_EQ(At<uint32_t>(b, 96), data_at);  // offset to point data
    EXPECT_EQ(At<uint32_t>(b, 100), 1u);      // one VLR
    EXPECT_EQ(At<uint8_t>(b, 104), 6);        // point data record format
    EXPECT_EQ(At<uint16_t>(b, 105), record);
    EXPECT_EQ(At<uint32_t>(b, 107), 0u);      // legacy count: 0 for format 6
    EXPECT_EQ(At<uint64_t>(b, 247), 1000u);   // number of point records
    EXPECT_EQ(At<uint64_t>(b, 255), 1000u);   // of them first returns
    EXPECT_EQ(At<double>(b, 131), 1e-4);      // x scale
    EXPECT_EQ(At<double>(b, 155), 512300.0);  // x offset: the minimum's whole metre
    EXPECT_EQ(At<double>(b, 163), 5403100.0);
    EXPECT_EQ(At<double>(b, 171), 300.0);
    // Bounds: max x, min x, ... enclose the points.
    double lo = 1e300, hi = -1e300;
    for (const auto& p : d.xyz) lo = std::min(lo, p.x()), hi = std::max(hi, p.x());
    EXPECT_NEAR(At<double>(b, 179), hi, 1e-4);
    EXPECT_NEAR(At<double>(b, 187), lo, 1e-4);
    // The Extra Bytes VLR: LASF_Spec / 4, three descriptors.
    EXPECT_STREQ(b.data() + 375 + 2, "LASF_Spec");
    EXPECT_EQ(At<uint16_t>(b, 375 + 18), 4);
    EXPECT_EQ(At<uint16_t>(b, 375 + 20), 3 * 192);
    const size_t e0 = 375 + 54;
    EXPECT_EQ(At<uint8_t>(b, e0 + 2), 9);  // float
    EXPECT_EQ(At<uint8_t>(b, e0 + 3), 1);  // no_data given
    EXPECT_STREQ(b.data() + e0 + 4, "distance");
    EXPECT_EQ(At<double>(b, e0 + 40), 1e9);
    EXPECT_EQ(At<uint8_t>(b, e0 + 192 + 2), 6);  // int32
    EXPECT_EQ(At<int64_t>(b, e0 + 192 + 40), -1);
    EXPECT_EQ(At<uint8_t>(b, e0 + 2 * 192 + 3), 0);  // keyframes: no no_data
    // The first point record: return 1 of 1, its class, source and time.
    EXPECT_EQ(At<uint8_t>(b, data_at + 14), 0x11);
    EXPECT_EQ(At<uint8_t>(b, data_at + 16), kLasClassBuilding);
    EXPECT_EQ(At<uint16_t>(b, data_at + 20), 1);
    EXPECT_EQ(At<double>(b, data_at + 22), 4.8e8);
    EXPECT_EQ(At<float>(b, data_at + 30), 1e9f);
}

TEST(Las, RoundTripKeepsEveryValue) {
    test::TempDir dir;
    const LasData d = Sample(5000);
    WriteLas(dir / "m.las", d);
    const LasData r = ReadLas(dir / "m.las");
    ASSERT_EQ(r.size(), d.size());
    EXPECT_TRUE(r.adjusted_standard_gps_time);
    EXPECT_EQ(r.file_source_id, 2);
    EXPECT_EQ(r.scale, 1e-4);
    for (size_t i = 0; i < d.size(); ++i) {
        ASSERT_LE((r.xyz[i] - d.xyz[i]).cwiseAbs().maxCoeff(), 0.5e-4 + 1e-9) << i;
    }
    EXPECT_EQ(r.classification, d.classification);
    EXPECT_EQ(r.user_data, d.user_data);
    EXPECT_EQ(r.point_source_id, d.point_source_id);
    EXPECT_EQ(r.gps_time, d.gps_time);
    ASSERT_EQ(r.extra.size(), 3u);
    for (const LasExtraField& f : d.extra) {
        const LasExtraField* g = r.Find(f.name);
        ASSERT_NE(g, nullptr) << f.name;
        EXPECT_EQ(g->type, f.type);
        EXPECT_EQ(g->description, f.description);
        EXPECT_EQ(g->no_data, f.no_data);
        EXPECT_EQ(g->values, f.values) << f.name;  // all float-representable
    }
    // Written again from what was read: the same bytes.
    EXPECT_EQ(SerializeLas(r), ReadFileToString(dir / "m.las"));
}

TEST(Las, EmptyCloudAndNoExtraFields) {
    LasData d;
    const LasData r = ParseLas("empty", SerializeLas(d));
    EXPECT_EQ(r.size(), 0u);
    EXPECT_TRUE(r.extra.empty());
    // An empty map keeps its fields (a project whose visits anchored nothing).
    d.extra = {LasExtraField{"first_visit", LasType::kUint16, "", {}, {}}};
    const LasData e = ParseLas("empty", SerializeLas(d));
    EXPECT_EQ(e.size(), 0u);
    ASSERT_EQ(e.extra.size(), 1u);
    EXPECT_EQ(e.extra[0].name, "first_visit");
    d.extra.clear();
    d.xyz = {{1, 2, 3}};
    d.adjusted_standard_gps_time = false;
    const std::string b = SerializeLas(d);
    EXPECT_EQ(b.size(), 375u + 30u);
    EXPECT_EQ(At<uint16_t>(b, 6), 0x10);  // GPS week time
    EXPECT_EQ(ParseLas("one", b).xyz[0], Eigen::Vector3d(1, 2, 3));
}

TEST(Las, WriterRefusesWhatTheFormatCannotHold) {
    test::TempDir dir;
    LasData d = Sample(10);
    d.gps_time.pop_back();
    EXPECT_THROW(SerializeLas(d), Error);
    try {
        WriteLas(dir / "bad.las", d);
        FAIL() << "no error";
    } catch (const FileError& e) {
        EXPECT_NE(std::string(e.what()).find("bad.las"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("gps_time"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(dir / "bad.las"));
    d = Sample(10);
    d.extra[0].values.pop_back();
    EXPECT_THROW(SerializeLas(d), Error);
    d = Sample(10);
    d.extra[1].values[3] = 0.5;  // not an integer
    EXPECT_THROW(SerializeLas(d), Error);
    d = Sample(10);
    d.extra[2].values[3] = 70000;  // beyond uint16
    EXPECT_THROW(SerializeLas(d), Error);
    d = Sample(10);
    d.extra[1].name = "distance";  // twice
    EXPECT_THROW(SerializeLas(d), Error);
    d = Sample(10);
    d.extra[0].name = std::string(32, 'n');  // no room for the NUL
    EXPECT_THROW(SerializeLas(d), Error);
    d = Sample(10);
    d.xyz[4].x() = d.xyz[0].x() + 3e5;  // 3e9 counts of 0.1 mm from the offset
    EXPECT_THROW(SerializeLas(d), Error);
    d = Sample(10);
    d.xyz[4].z() = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(SerializeLas(d), Error);
    d = Sample(10);
    d.gps_time[2] = std::numeric_limits<double>::infinity();
    EXPECT_THROW(SerializeLas(d), Error);
}

TEST(Las, ReaderNamesTheFileAndWhatIsWrong) {
    const std::string good = SerializeLas(Sample(20));
    const auto fails = [](const std::string& bytes, const std::string& what) {
        try {
            ParseLas("x.las", bytes);
            ADD_FAILURE() << "no error for " << what;
        } catch (const FileError& e) {
            EXPECT_NE(std::string(e.what()).find("x.las"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    };
    fails(good.substr(0, 100), "too short");
    fails("LASX" + good.substr(4), "signature");
    std::string b = good;
    b[25] = 2;
    fails(b, "LAS 1.2");
    b = good;
    b[104] = char(6 | 0x80);
    fails(b, "compressed");
    b = good;
    b[104] = 1;
    fails(b, "point format 1");
    fails(good.substr(0, good.size() - 1), "truncated");
    b = good;
    b[375 + 20] = 100;  // an Extra Bytes VLR of 100 bytes
    b[375 + 21] = 0;
    fails(b, "multiple of 192");
}

// Mutants of a file (header, VLR and points) are read or refused naming the file, never a crash
// (the ASan build runs this).
TEST(Las, ReaderSurvivesMutations) {
    const auto [parsed, rejected] = test::FuzzReader(
        "fuzz.las", {{SerializeLas(Sample(8)), 375 + 54 + 3 * 192}}, 3000, 34, test::kMutationBytes,
        [](const std::string& b) { ParseLas("fuzz.las", b); });
    EXPECT_GT(rejected, 300u);
    EXPECT_GT(parsed, 300u);
}

TEST(Las, AdjustedStandardGpsTimeOfUnixTimes) {
    constexpr int64_t kNs = 1'000'000'000;
    // 2017-01-01T00:00:00Z is GPS second 1 167 264 018 (18 leap seconds); the second before it
    // had 17.
    EXPECT_EQ(UnixNsToAdjustedGpsSeconds(1483228800 * kNs), 167264018.0);
    EXPECT_EQ(UnixNsToAdjustedGpsSeconds(1483228799 * kNs), 167264016.0);
    // The GPS epoch itself, and a time with nanoseconds (exact to a microsecond).
    EXPECT_EQ(UnixNsToAdjustedGpsSeconds(315964800 * kNs), -1e9);
    EXPECT_NEAR(UnixNsToAdjustedGpsSeconds(1796083200 * kNs + 123456789),
                1796083200.0 - 315964800 + 18 - 1e9 + 0.123456789, 1e-6);
}

TEST(Las, CreationDateIsTheUtcDayOfTheYear) {
    constexpr int64_t kNs = 1'000'000'000;
    LasData d;
    SetLasCreationDate(d, 1796083200 * kNs);  // 2026-12-01T00:00:00Z
    EXPECT_EQ(d.creation_year, 2026);
    EXPECT_EQ(d.creation_day_of_year, 335);
    SetLasCreationDate(d, 1483228799 * kNs);  // 2016-12-31T23:59:59Z, a leap year's last day
    EXPECT_EQ(d.creation_year, 2016);
    EXPECT_EQ(d.creation_day_of_year, 366);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::io
