// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/pcd.hpp"

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
using common::FileError;

constexpr uint32_t kExactBelowNs = 15'625'000;  // 2^-6 s: float spacing <= 0.93 ns below it

// |read back - written| for a time offset: float32 seconds keep 24 significant bits.
int64_t TimeBoundNs(uint32_t ns) {
    if (ns < kExactBelowNs) return 0;
    return static_cast<int64_t>(std::ldexp(static_cast<double>(ns), -24) + 0.5);
}

void ExpectSameExceptTime(const common::PointCloud& a, const common::PointCloud& b) {
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(a.xyz, b.xyz);  // == on float: bit-exact for finite values
    EXPECT_EQ(a.intensity, b.intensity);
    EXPECT_EQ(a.ring, b.ring);
    ASSERT_EQ(a.time_offset_ns.size(), b.time_offset_ns.size());
}

void ExpectTimesWithinBound(const common::PointCloud& written, const common::PointCloud& read) {
    ASSERT_EQ(written.time_offset_ns.size(), read.time_offset_ns.size());
    for (size_t i = 0; i < written.size(); ++i) {
        const uint32_t ns = written.time_offset_ns[i];
        ASSERT_LE(std::abs(int64_t{read.time_offset_ns[i]} - ns), TimeBoundNs(ns)) << i;
    }
}

template <typename T>
void Put(std::string& out, T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    out.append(b, sizeof(T));
}

TEST(Pcd, BinaryRoundTripIsBitExact) {
    test::TempDir dir;
    const auto cloud = test::MakeRoomScan(32, 1024, 3);
    WritePcd(dir / "s.pcd", cloud, PcdEncoding::kBinary);
    const auto back = ReadPcd(dir / "s.pcd");
    ExpectSameExceptTime(cloud, back);
    ExpectTimesWithinBound(cloud, back);
    // Reading maps t to the nearest ns, which maps back to the same float: files are stable.
    EXPECT_EQ(SerializePcd(back, PcdEncoding::kBinary), ReadFileToString(dir / "s.pcd"));
}

TEST(Pcd, AsciiRoundTripIsBitExact) {
    test::TempDir dir;
    const auto cloud = test::MakeRoomScan(32, 1024, 4);
    WritePcd(dir / "s.pcd", cloud, PcdEncoding::kAscii);
    const auto back = ReadPcd(dir / "s.pcd");
    ExpectSameExceptTime(cloud, back);
    ExpectTimesWithinBound(cloud, back);
    EXPECT_EQ(SerializePcd(back, PcdEncoding::kAscii), ReadFileToString(dir / "s.pcd"));
    // Binary and ASCII read back to the same cloud.
    const auto bin = ParsePcd("b", SerializePcd(cloud, PcdEncoding::kBinary));
    EXPECT_EQ(bin.time_offset_ns, back.time_offset_ns);
}

TEST(Pcd, WritesThePclHeaderAndPackedPoints) {
    common::PointCloud c;
    c.PushBack({1.0f, -2.0f, 0.5f}, 7.0f, 3, 50'000'000);
    c.PushBack({0.25f, 4.0f, -8.0f}, 9.5f, 31, 0);
    const std::string header =
        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z intensity ring t\n"
        "SIZE 4 4 4 4 2 4\nTYPE F F F F U F\nCOUNT 1 1 1 1 1 1\nWIDTH 2\nHEIGHT 1\n"
        "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\n";
    EXPECT_EQ(SerializePcd(c, PcdEncoding::kAscii),
              header + "DATA ascii\n1 -2 0.5 7 3 0.05\n0.25 4 -8 9.5 31 0\n");
    const std::string bin = SerializePcd(c, PcdEncoding::kBinary);
    ASSERT_EQ(bin.size(), header.size() + 12 + 2 * 22);  // AoS, 22 bytes a point, no padding
    std::string point;
    for (float v : {1.0f, -2.0f, 0.5f, 7.0f}) Put(point, v);
    Put(point, uint16_t{3});
    Put(point, 0.05f);
    EXPECT_EQ(bin.substr(header.size() + 12, 22), point);
    // Only the channels the cloud has.
    common::PointCloud xyz;
    xyz.PushBack({1.0f, 2.0f, 3.0f});
    EXPECT_NE(SerializePcd(xyz, PcdEncoding::kAscii).find("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F"),
              std::string::npos);
    const auto back = ParsePcd("xyz", SerializePcd(xyz, PcdEncoding::kBinary));
    EXPECT_EQ(back.xyz, xyz.xyz);
    EXPECT_FALSE(back.HasIntensity() || back.HasRing() || back.HasTime());
    EXPECT_TRUE(ParsePcd("e", SerializePcd(common::PointCloud{}, PcdEncoding::kBinary)).empty());
}

TEST(Pcd, TimeOffsetRoundTripIsExactBelow15msAndWithin7nsTo200ms) {
    // float32 seconds has a 2^-26 s (~15 ns) spacing between 0.125 and 0.25 s, so t is NOT exact
    // at ns resolution over a 0.1 s scan; this pins down the real bound.
    std::mt19937 rng(5);
    int64_t worst = 0;
    size_t inexact = 0, n = 0;
    for (uint32_t ns = 0; ns <= 200'000'000; ns += 1 + rng() % 20'000, ++n) {
        const int64_t back = PcdSecondsToNs(PcdNsToSeconds(ns));
        const int64_t err = std::abs(back - ns);
        if (ns < kExactBelowNs) {
            ASSERT_EQ(err, 0) << ns;
        }
        ASSERT_LE(err, 7) << ns;
        worst = std::max(worst, err);
        inexact += err != 0;
    }
    EXPECT_EQ(worst, 7);
    EXPECT_GT(inexact, n / 2);
    const uint32_t max = std::numeric_limits<uint32_t>::max();
    EXPECT_LE(std::abs(PcdSecondsToNs(PcdNsToSeconds(max)) - max), 256);  // 2^-24 * 4.3 s
}

TEST(Pcd, ReadsPclPointCloud2WithPaddingFields) {
    // pcl::PointXYZI through PCLPointCloud2: 4 bytes of padding after z, 12 after intensity.
    std::string f =
        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z _ intensity _\n"
        "SIZE 4 4 4 1 4 1\nTYPE F F F U F U\nCOUNT 1 1 1 4 1 12\nWIDTH 2\nHEIGHT 1\n"
        "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA binary\n";
    for (int i = 0; i < 2; ++i) {
        for (float v : {1.0f + i, 2.0f, 3.0f}) Put(f, v);
        f.append(4, '\x7f');
        Put(f, 10.0f * i);
        f.append(12, '\xff');
    }
    f.append(100, '\0');  // PCL's binary writer leaves zero padding after the points
    const auto c = ParsePcd("xyzi.pcd", f);
    ASSERT_EQ(c.size(), 2u);
    EXPECT_EQ(c.xyz[1], Eigen::Vector3f(2, 2, 3));
    EXPECT_EQ(c.intensity[1], 10.0f);
    EXPECT_FALSE(c.HasRing() || c.HasTime());
}

TEST(Pcd, ReadsOusterRosPointsWithNanosecondTime) {
    // ouster_ros::Point: t is uint32 nanoseconds, ring uint16, plus fields we skip.
    std::string f =
        "FIELDS x y z _ intensity t reflectivity ring ambient _ range _\n"
        "SIZE 4 4 4 1 4 4 2 2 2 1 4 1\nTYPE F F F U F U U U U U U U\n"
        "COUNT 1 1 1 4 1 1 1 1 1 2 1 12\nWIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\n"
        "DATA binary\n";
    for (float v : {1.5f, -2.5f, 0.125f}) Put(f, v);
    f.append(4, '\0');
    Put(f, 321.0f);
    Put(f, uint32_t{99'999'999});
    Put(f, uint16_t{7});
    Put(f, uint16_t{31});
    Put(f, uint16_t{400});
    f.append(2, '\0');
    Put(f, uint32_t{12345});
    f.append(12, '\0');
    const auto c = ParsePcd("os.pcd", f);
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(c.xyz[0], Eigen::Vector3f(1.5f, -2.5f, 0.125f));
    EXPECT_EQ(c.intensity[0], 321.0f);
    EXPECT_EQ(c.ring[0], 31);
    EXPECT_EQ(c.time_offset_ns[0], 99'999'999u);  // integers are exact nanoseconds
}

TEST(Pcd, ReadsAsciiWithCountAboveOneOtherTypesAndOldHeaders) {
    // COUNT 3 descriptor, x as double, intensity int16, ring float, t double seconds, rgb as
    // PCL writes it in ASCII (an integer).
    const auto c = ParsePcd("d.pcd",
                            "# .PCD v0.7\nVERSION .7\nFIELDS x y z rgb d intensity ring t\n"
                            "SIZE 8 4 4 4 4 2 4 8\nTYPE F F F U F I F F\nCOUNT 1 1 1 1 3 1 1 1\n"
                            "WIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n"
                            "0.1 2 3 4278190335 1 2 3 -5 4 0.0000001\r\n"
                            "\n"
                            "-1e3 +2 3 0 nan nan nan 300 0 0.123456789\n");
    ASSERT_EQ(c.size(), 2u);
    EXPECT_EQ(c.xyz[0].x(), 0.1f);
    EXPECT_EQ(c.xyz[1].x(), -1000.0f);
    EXPECT_EQ(c.intensity[0], -5.0f);
    EXPECT_EQ(c.ring[0], 4);
    EXPECT_EQ(c.time_offset_ns[0], 100u);
    EXPECT_EQ(c.time_offset_ns[1], 123'456'789u);
    // v0.6: no VERSION, no VIEWPOINT; v0.5: COLUMNS and no SIZE/TYPE/COUNT (float32).
    const auto v6 = ParsePcd("v6.pcd",
                             "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nPOINTS 1\n"
                             "DATA ascii\n1 2 3\n");
    EXPECT_EQ(v6.xyz.at(0), Eigen::Vector3f(1, 2, 3));
    const auto v5 = ParsePcd("v5.pcd", "COLUMNS x y z\nPOINTS 1\nDATA ascii\n1 2 3");
    EXPECT_EQ(v5.xyz.at(0), Eigen::Vector3f(1, 2, 3));
    // Integer x y z of every size, signed and unsigned.
    std::string ints = "FIELDS x y z\nSIZE 1 2 8\nTYPE I U I\nWIDTH 1\nPOINTS 1\nDATA binary\n";
    Put(ints, int8_t{-7});
    Put(ints, uint16_t{65535});
    Put(ints, int64_t{-123456});
    EXPECT_EQ(ParsePcd("i.pcd", ints).xyz.at(0), Eigen::Vector3f(-7, 65535, -123456));
}

TEST(Pcd, OrganizedCloudsDropNanPointsUnorganizedRejectThem) {
    const std::string head = "FIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\n";
    const std::string body = "DATA ascii\n1 2 3 4\nnan nan nan 0\n5 6 7 8\n-nan 1 1 nan\n";
    const auto c = ParsePcd("o.pcd", head + "WIDTH 2\nHEIGHT 2\nPOINTS 4\n" + body);
    ASSERT_EQ(c.size(), 2u);
    EXPECT_EQ(c.xyz[1], Eigen::Vector3f(5, 6, 7));
    EXPECT_EQ(c.intensity[1], 8.0f);
    EXPECT_FILE_ERROR(ParsePcd("u.pcd", head + "WIDTH 4\nHEIGHT 1\nPOINTS 4\n" + body), "u.pcd", 9);
    // A NaN intensity of a kept point is an error even in an organized cloud.
    EXPECT_FILE_ERROR(ParsePcd("o.pcd", head + "WIDTH 1\nHEIGHT 2\nPOINTS 2\n" +
                                            "DATA ascii\n1 2 3 4\n1 2 3 inf\n"),
                      "o.pcd", 9);
}

TEST(Pcd, ReadsPclBinaryCompressed) {
    // Written by pcl_convert_pcd_ascii_binary (PCL 1.13) ... 2 from an 8-point ASCII cloud with
    // intensity COUNT 4; PCL's trailing zero padding left out.
    const std::string header =
        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z intensity ring t\n"
        "SIZE 4 4 4 4 2 4\nTYPE F F F F U F\nCOUNT 1 1 1 4 1 1\nWIDTH 8\nHEIGHT 1\n"
        "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 8\nDATA binary_compressed\n";
    const std::string lzf(
        "\x4b\x00\x00\x00\x10\x01\x00\x00\x04\x00\x00\x80\x3f\x00\xe0\x04\x03\x00\xc0\x20\x0f\xe0"
        "\x03\x03\x02\x00\x40\x00\xe0\x05\x03\x00\xc0\x20\x0f\xe0\x02\x03\x00\x40\x20\x1f\xe0\x13"
        "\x03\x02\x20\x41\x00\xe0\x34\x03\x00\xa0\x20\x3f\xe0\x33\x03\x04\x01\x00\x02\x00\x03\x20"
        "\xb2\xc0\x07\xe0\x05\x00\x03\xcd\xcc\x4c\x3d\xe0\x01\x03\x01\x4c\x3d",
        83);
    const auto c = ParsePcd("c.pcd", header + lzf);
    ASSERT_EQ(c.size(), 8u);
    for (size_t i = 0; i < 8; ++i) {
        const bool second = i >= 4;
        EXPECT_EQ(c.xyz[i], Eigen::Vector3f(second ? 1.5f : 1.0f, second ? -2.0f : 2.0f, 3.0f));
        EXPECT_EQ(c.intensity[i], second ? 20.0f : 10.0f);
        EXPECT_EQ(c.ring[i], i % 4);
        EXPECT_EQ(c.time_offset_ns[i], second ? PcdSecondsToNs(0.05f) : 0);  // 50000001 ns
    }
    // Damaged streams and lying sizes.
    std::string bad = header + lzf;
    bad[header.size() + 8] = '\xe0';  // a back reference before the start of the output
    EXPECT_FILE_ERROR(ParsePcd("c.pcd", bad), "c.pcd", 0);
    EXPECT_FILE_ERROR(ParsePcd("c.pcd", header + lzf.substr(0, 40)), "c.pcd", 0);
    std::string big = header + lzf;
    big.replace(big.find("POINTS 8"), 8, "POINTS 9");
    big.replace(big.find("WIDTH 8"), 7, "WIDTH 9");
    EXPECT_FILE_ERROR(ParsePcd("c.pcd", big), "c.pcd", 0);
}

TEST(Pcd, RejectsBadHeadersNamingTheLine) {
    const std::string ok_fields = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n";
    EXPECT_FILE_ERROR(ParsePcd("e.pcd", ""), "e.pcd", 1);
    EXPECT_FILE_ERROR(ParsePcd("g.pcd", "\x89PNG\r\n\x1a\n"), "g.pcd", 1);
    EXPECT_FILE_ERROR(ParsePcd("h.pcd", "# .PCD v0.7\nVERSION 0.7\n"), "h.pcd", 2);
    EXPECT_FILE_ERROR(ParsePcd("h.pcd", "FIELDS x y z\nSIZE 4 4\n"), "h.pcd", 2);
    EXPECT_FILE_ERROR(ParsePcd("h.pcd", "FIELDS x y z\nSIZE 4 4 3\nTYPE F F F\n"), "h.pcd", 3);
    EXPECT_FILE_ERROR(ParsePcd("h.pcd", "FIELDS x y z\nTYPE F F F\nSIZE 4 4 2\n"), "h.pcd", 3);
    EXPECT_FILE_ERROR(ParsePcd("h.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F Q\n"), "h.pcd", 3);
    EXPECT_FILE_ERROR(ParsePcd("h.pcd", "FIELDS x y z\nCOUNT 1 0 1\n"), "h.pcd", 2);
    EXPECT_FILE_ERROR(ParsePcd("h.pcd", ok_fields + "COUNT 1 1 1\n"), "h.pcd", 5);
    EXPECT_FILE_ERROR(ParsePcd("h.pcd", ok_fields + "WIDTH -1\n"), "h.pcd", 5);
    EXPECT_FILE_ERROR(ParsePcd("h.pcd", ok_fields + "WIDTH 99999999999\n"), "h.pcd", 5);
    EXPECT_FILE_ERROR(ParsePcd("h.pcd", ok_fields + "WIDTH 2\nHEIGHT 1\nPOINTS 3\nDATA ascii\n"),
                      "h.pcd", 8);
    EXPECT_FILE_ERROR(ParsePcd("h.pcd", ok_fields + "WIDTH 1\nVIEWPOINT 0 0 0 1 0 0 nan\n"),
                      "h.pcd", 6);
    EXPECT_FILE_ERROR(ParsePcd("h.pcd", ok_fields + "WIDTH 1\nDATA ascii_gz\n"), "h.pcd", 6);
    EXPECT_FILE_ERROR(ParsePcd("h.pcd", ok_fields + "WIDTH 1\nHEIGTH 1\n"), "h.pcd", 6);
    EXPECT_FILE_ERROR(ParsePcd("h.pcd", "FIELDS x y x\n"), "h.pcd", 1);
    EXPECT_FILE_ERROR(ParsePcd("h.pcd", "FIELDS x y\nWIDTH 1\nDATA ascii\n1 2\n"), "h.pcd", 3);
    EXPECT_FILE_ERROR(ReadPcd("/nonexistent/k.pcd"), "/nonexistent/k.pcd", 0);
}

TEST(Pcd, RejectsBadAsciiBodiesNamingTheLine) {
    // Line 12 is the first point of a file we write.
    const std::string good = SerializePcd(test::MakeRoomScan(2, 3, 1), PcdEncoding::kAscii);
    const size_t p1 = good.find("DATA ascii\n") + 11;
    auto with_line = [&](const std::string& line) {
        return good.substr(0, p1) + line + "\n" + good.substr(good.find('\n', p1) + 1);
    };
    EXPECT_EQ(ParsePcd("a.pcd", with_line("1 2 3 4 5 0.01")).ring.at(0), 5);
    EXPECT_FILE_ERROR(ParsePcd("a.pcd", with_line("1 2 3 4 5")), "a.pcd", 12);
    EXPECT_FILE_ERROR(ParsePcd("a.pcd", with_line("1 2 3 4 5 0.01 7")), "a.pcd", 12);
    EXPECT_FILE_ERROR(ParsePcd("a.pcd", with_line("1 2 nan 4 5 0.01")), "a.pcd", 12);
    EXPECT_FILE_ERROR(ParsePcd("a.pcd", with_line("1 2 1e39 4 5 0.01")), "a.pcd", 12);
    EXPECT_FILE_ERROR(ParsePcd("a.pcd", with_line("1 2 3 inf 5 0.01")), "a.pcd", 12);
    EXPECT_FILE_ERROR(ParsePcd("a.pcd", with_line("1 2 3 4 65536 0.01")), "a.pcd", 12);
    EXPECT_FILE_ERROR(ParsePcd("a.pcd", with_line("1 2 3 4 -1 0.01")), "a.pcd", 12);
    EXPECT_FILE_ERROR(ParsePcd("a.pcd", with_line("1 2 3 4 5 -0.01")), "a.pcd", 12);
    EXPECT_FILE_ERROR(ParsePcd("a.pcd", with_line("1 2 3 4 5 4.3")), "a.pcd", 12);
    EXPECT_FILE_ERROR(ParsePcd("a.pcd", with_line("1 2 3 4 5 nan")), "a.pcd", 12);
    EXPECT_FILE_ERROR(ParsePcd("a.pcd", with_line("1 2 3x 4 5 0")), "a.pcd", 12);
    EXPECT_FILE_ERROR(ParsePcd("a.pcd", with_line(std::string("1 2 3\0 4 5 0", 12))), "a.pcd", 12);
    // Truncated in the middle of the last line, at a line end, and an extra point.
    const size_t last = good.rfind('\n', good.size() - 2) + 1;
    EXPECT_FILE_ERROR(ParsePcd("a.pcd", good.substr(0, last + 8)), "a.pcd", 17);
    EXPECT_FILE_ERROR(ParsePcd("a.pcd", good.substr(0, last)), "a.pcd", 16);
    EXPECT_FILE_ERROR(ParsePcd("a.pcd", good + "1 2 3 4 5 0\n"), "a.pcd", 18);
    // A lying POINTS is caught at the DATA line before anything is allocated.
    std::string lie = good;
    lie.replace(lie.find("WIDTH 6"), 7, "WIDTH 4000000000");
    lie.replace(lie.find("POINTS 6"), 8, "POINTS 4000000000");
    EXPECT_FILE_ERROR(ParsePcd("a.pcd", lie), "a.pcd", 11);
}

TEST(Pcd, RejectsBadBinaryBodiesWithoutLine) {
    const auto cloud = test::MakeRoomScan(2, 3, 1);
    const std::string good = SerializePcd(cloud, PcdEncoding::kBinary);
    const size_t data = good.size() - 6 * 22;
    EXPECT_FILE_ERROR(ParsePcd("b.pcd", good.substr(0, good.size() - 1)), "b.pcd", 0);
    EXPECT_FILE_ERROR(ParsePcd("b.pcd", good.substr(0, data)), "b.pcd", 0);
    std::string nan = good;
    const float q = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(nan.data() + data + 22 * 2 + 4, &q, 4);
    EXPECT_FILE_ERROR(ParsePcd("b.pcd", nan), "b.pcd", 0);
    std::string neg_t = good;
    const float minus = -1.0f;
    std::memcpy(neg_t.data() + data + 22 * 5 + 18, &minus, 4);
    EXPECT_FILE_ERROR(ParsePcd("b.pcd", neg_t), "b.pcd", 0);
    std::string lie = good;
    lie.replace(lie.find("WIDTH 6"), 7, "WIDTH 4000000000");
    lie.replace(lie.find("POINTS 6"), 8, "POINTS 4000000000");
    EXPECT_FILE_ERROR(ParsePcd("b.pcd", lie), "b.pcd", 0);
}

TEST(Pcd, WriterRejectsCloudsItCouldNotReadBack) {
    test::TempDir dir;
    auto cloud = test::MakeRoomScan(2, 3, 1);
    cloud.xyz[4].y() = std::numeric_limits<float>::infinity();
    EXPECT_FILE_ERROR(WritePcd(dir / "w.pcd", cloud), (dir / "w.pcd").string(), 0);
    cloud = test::MakeRoomScan(2, 3, 1);
    cloud.ring.pop_back();
    EXPECT_FILE_ERROR(WritePcd(dir / "w.pcd", cloud), (dir / "w.pcd").string(), 0);
    EXPECT_FALSE(std::filesystem::exists(dir / "w.pcd"));
}

// Random byte edits of valid files must only ever produce a cloud or a FileError (run under
// ASan and UBSan too).
constexpr char kInteresting[] = "0123456789 \n-.e+naFIU_\x00\xff\x7f";

TEST(Pcd, MutatedFilesOnlyEverThrowFileError) {
    const auto cloud = test::MakeRoomScan(2, 4, 9);
    std::vector<std::string> seeds = {SerializePcd(cloud, PcdEncoding::kBinary),
                                      SerializePcd(cloud, PcdEncoding::kAscii)};
    // A compressed file too (literal runs only: LZF control byte = length - 1).
    const std::string bin = seeds[0];
    const size_t data = bin.find("DATA binary\n") + 12;
    std::string soa;  // binary_compressed stores one block per field
    for (int f = 0; f < 6; ++f) {
        const size_t off[] = {0, 4, 8, 12, 16, 18}, size[] = {4, 4, 4, 4, 2, 4};
        for (size_t i = 0; i < cloud.size(); ++i)
            soa += bin.substr(data + i * 22 + off[f], size[f]);
    }
    std::string lzf;
    for (size_t i = 0; i < soa.size(); i += 32) {
        const std::string run = soa.substr(i, 32);
        lzf += static_cast<char>(run.size() - 1);
        lzf += run;
    }
    std::string compressed = bin.substr(0, data - 7) + "binary_compressed\n";
    Put(compressed, static_cast<uint32_t>(lzf.size()));
    Put(compressed, static_cast<uint32_t>(soa.size()));
    ASSERT_EQ(ParsePcd("c", compressed + lzf).xyz, ParsePcd("b", bin).xyz);
    seeds.push_back(compressed + lzf);
    std::vector<test::FuzzSeed> fuzz_seeds;
    for (const std::string& seed : seeds) fuzz_seeds.push_back({seed, seed.find("DATA ") + 20});
    const auto [parsed, rejected] = test::FuzzReader(
        "fuzz.pcd", fuzz_seeds, 3000, 2024, {kInteresting, sizeof(kInteresting) - 1},
        [](const std::string& b) { ParsePcd("fuzz.pcd", b); });
    EXPECT_GT(rejected, 1000u);
    EXPECT_GT(parsed, 100u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::io
