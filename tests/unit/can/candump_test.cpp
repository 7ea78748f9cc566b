// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/can/candump.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::can {
namespace {
namespace BIMSLAM_UNITY_ID {

using common::CanFrame;

struct Read {
    std::vector<CanFrame> frames;
    std::vector<std::string> interfaces;
    std::vector<uint64_t> lines;
    CandumpStats stats;
    bool truncated = false;
};

Read ReadAll(CandumpReader& reader) {
    Read out;
    CandumpRecord r;
    while (reader.Next(r)) {
        out.frames.push_back(r.frame);
        out.interfaces.emplace_back(r.interface_name);
        out.lines.push_back(r.line);
    }
    out.stats = reader.stats();
    out.truncated = reader.truncated();
    return out;
}

Read ReadText(const std::string& text, CandumpMode mode = CandumpMode::kStrict) {
    CandumpReaderConfig config;
    config.mode = mode;
    CandumpReader reader = CandumpReader::FromMemory("mem.log", text, config);
    return ReadAll(reader);
}

std::string WriteText(const Read& read, CandumpWriterConfig config = {}) {
    CandumpWriter writer(config);
    for (size_t i = 0; i < read.frames.size(); ++i)
        writer.Write(read.frames[i], read.interfaces[i]);
    return writer.text();
}

CanFrame ParseOne(const std::string& line) {
    CandumpLine out;
    CandumpIssue issue = CandumpIssue::kGarbage;
    std::string_view what;
    EXPECT_TRUE(ParseCandumpLine(line, out, issue, what)) << line << ": " << what;
    return out.frame;
}

// What candump -l writes (one interface name length: no padding), every kind of frame.
const char* const kCandumpLog =
    "(1699999999.123456) can0 100#0011223344556677\n"
    "(1699999999.123457) can0 0F0#\n"
    "(1699999999.200000) can0 1FFFFFFF#DEADBEEF\n"
    "(1699999999.200000) can0 00000001#01\n"
    "(1699999999.300000) can0 123#R\n"
    "(1699999999.300001) can0 123#R8\n"
    "(1699999999.300002) can0 123#R8_F\n"
    "(1699999999.300003) can0 12345678#R3\n"
    "(1699999999.400000) can0 7FF##1000102030405060708090A0B\n"
    "(1699999999.400001) can0 1ABCDEF0##5"
    "000102030405060708090A0B0C0D0E0F101112131415161718191A1B1C1D1E1F"
    "202122232425262728292A2B2C2D2E2F303132333435363738393A3B3C3D3E3F\n"
    "(1699999999.400002) can0 001##0\n"
    "(1699999999.400003) can0 002##3AA\n"
    "(1699999999.500000) can0 20000080#0000000000000000\n"
    "(1699999999.500001) can0 20000204#0004000000000000\n"
    "(1699999999.600000) can0 111#1122334455667788_9\n"
    "(1699999999.600000) can0 000#00\n";

TEST(CandumpParse, ClassicStandardAndExtended) {
    CanFrame f = ParseOne("(1699999999.123456) can0 100#0011223344556677");
    EXPECT_EQ(f.timestamp_ns, 1699999999123456000);
    EXPECT_EQ(f.id, 0x100u);
    EXPECT_FALSE(f.extended);
    EXPECT_FALSE(f.fd);
    EXPECT_FALSE(f.remote);
    EXPECT_FALSE(f.error);
    ASSERT_EQ(f.len, 8);
    for (int i = 0; i < 8; ++i) EXPECT_EQ(f.data[i], 0x11 * i);

    f = ParseOne("(0.297000) vcan2 1FFFFFFF#deadBEEF");
    EXPECT_EQ(f.timestamp_ns, 297000000);
    EXPECT_TRUE(f.extended);
    EXPECT_EQ(f.id, 0x1FFFFFFFu);
    ASSERT_EQ(f.len, 4);
    EXPECT_EQ(f.data[0], 0xDE);
    EXPECT_EQ(f.data[3], 0xEF);

    // Extended with a small value: still 8 digits, still extended.
    f = ParseOne("(1.000001) can0 00000123#");
    EXPECT_TRUE(f.extended);
    EXPECT_EQ(f.id, 0x123u);
    EXPECT_EQ(f.len, 0);
}

TEST(CandumpParse, RemoteFrames) {
    CanFrame f = ParseOne("(1.0) can0 123#R");
    EXPECT_TRUE(f.remote);
    EXPECT_EQ(f.len, 0);
    f = ParseOne("(1.0) can0 123#r5");
    EXPECT_TRUE(f.remote);
    EXPECT_EQ(f.len, 5);
    f = ParseOne("(1.0) can0 123#R8_C");
    EXPECT_EQ(f.len, 8);
    EXPECT_EQ(f.len8_dlc, 0xC);
    f = ParseOne("(1.0) can0 1234ABCD#R2");
    EXPECT_TRUE(f.remote);
    EXPECT_TRUE(f.extended);
    EXPECT_EQ(f.id, 0x1234ABCDu);
    EXPECT_EQ(f.len, 2);
    for (uint8_t b : f.data) EXPECT_EQ(b, 0);
}

TEST(CandumpParse, CanFdFrames) {
    CanFrame f = ParseOne("(1.0) can0 123##1001122");
    EXPECT_TRUE(f.fd);
    EXPECT_EQ(f.fd_flags, 1);
    ASSERT_EQ(f.len, 3);
    EXPECT_EQ(f.data[2], 0x22);
    f = ParseOne("(1.0) can0 12345678##5" + std::string(128, 'A'));
    EXPECT_TRUE(f.fd);
    EXPECT_TRUE(f.extended);
    EXPECT_EQ(f.fd_flags, 5);  // BRS | FDF, as Linux >= 6.2 reports
    EXPECT_EQ(f.len, 64);
    EXPECT_EQ(f.data[63], 0xAA);
    f = ParseOne("(1.0) can0 123##0");
    EXPECT_TRUE(f.fd);
    EXPECT_EQ(f.len, 0);
    for (unsigned len : {12u, 16u, 20u, 24u, 32u, 48u}) {
        f = ParseOne("(1.0) can0 123##0" + std::string(2 * len, '0'));
        EXPECT_EQ(f.len, len);
    }
}

TEST(CandumpParse, ErrorFrames) {
    const CanFrame f = ParseOne("(1.0) can0 20000084#0004000000000000");
    EXPECT_TRUE(f.error);
    EXPECT_FALSE(f.extended);
    EXPECT_EQ(f.id, 0x84u);  // CAN_ERR_BUSERROR | CAN_ERR_CRTL
    EXPECT_EQ(f.len, 8);
    EXPECT_EQ(f.data[1], 0x04);
}

TEST(CandumpParse, WhatOtherWritersProduce) {
    // Padded interface names, tabs, CR LF, '.' between bytes, a -x direction, 1..9 fraction digits.
    CandumpLine out;
    CandumpIssue issue{};
    std::string_view what;
    ASSERT_TRUE(ParseCandumpLine("(0000000001.000001)   can0 123#11.22.33\r", out, issue, what));
    EXPECT_EQ(out.interface_name, "can0");
    EXPECT_EQ(out.frame.len, 3);
    EXPECT_EQ(out.frame.data[2], 0x33);
    ASSERT_TRUE(ParseCandumpLine("(1.5)\tvcan10\t123#00 R", out, issue, what));
    EXPECT_EQ(out.interface_name, "vcan10");
    EXPECT_EQ(out.frame.timestamp_ns, 1'500'000'000);
    EXPECT_EQ(ParseOne("(1.123456789) can0 123#").timestamp_ns, 1'123'456'789);
    EXPECT_EQ(ParseOne("(0.000000001) can0 123#").timestamp_ns, 1);
    EXPECT_EQ(ParseOne("(9223372036.854775807) can0 123#").timestamp_ns, INT64_MAX);
}

TEST(CandumpRoundTrip, CandumpTextIsReproducedExactly) {
    const Read read = ReadText(kCandumpLog);
    EXPECT_EQ(read.frames.size(), 16u);
    EXPECT_EQ(read.stats.frames, 16u);
    EXPECT_EQ(read.stats.skipped_lines(), 0u);
    // candump pads seconds to 10 digits; these already have 10.
    EXPECT_EQ(WriteText(read), kCandumpLog);
}

TEST(CandumpRoundTrip, PaddingOptions) {
    // Unpadded seconds (the scapy-made gmlan log) and names right-aligned to the longest one
    // (candump -l with several interfaces).
    const std::string text =
        "(0.297000)  can0 12A#122010FF00001080\n"
        "(2.713000) vcan1 1E1#00000400000000\n";
    const Read read = ReadText(text);
    ASSERT_EQ(read.frames.size(), 2u);
    CandumpWriterConfig config;
    config.seconds_width = 1;
    config.interface_width = 5;
    EXPECT_EQ(WriteText(read, config), text);
    // candump's own form: seconds zero-padded to 10 digits.
    config = {};
    EXPECT_EQ(WriteText(read, config),
              "(0000000000.297000) can0 12A#122010FF00001080\n"
              "(0000000002.713000) vcan1 1E1#00000400000000\n");
}

TEST(CandumpWriter, RefusesWhatCannotBeWritten) {
    CandumpWriter writer(CandumpWriterConfig{});
    CanFrame f;
    f.id = 0x800;  // standard id above 0x7FF
    EXPECT_THROW(writer.Write(f, "can0"), common::Error);
    f.id = 0x123;
    f.len = 9;  // classic
    EXPECT_THROW(writer.Write(f, "can0"), common::Error);
    f.len = 1;
    f.timestamp_ns = -1;
    EXPECT_THROW(writer.Write(f, "can0"), common::Error);
    f.timestamp_ns = 0;
    EXPECT_THROW(writer.Write(f, ""), common::Error);
    EXPECT_THROW(writer.Write(f, "can 0"), common::Error);
    EXPECT_THROW(writer.Write(f, "a_very_long_interface"), common::Error);
    f.fd = true;
    f.len = 9;  // no DLC gives 9 bytes
    EXPECT_THROW(writer.Write(f, "can0"), common::Error);
    f.fd = false;
    f.len = 1;
    writer.Write(f, "can0");
    EXPECT_EQ(writer.text(), "(0000000000.000000) can0 123#00\n");
    EXPECT_EQ(writer.frames(), 1u);

    char small[16];
    EXPECT_EQ(FormatCandumpLine(f, "can0", small), 0u);
}

TEST(CandumpWriter, SubMicrosecondsAreCutAsCandumpDoes) {
    CanFrame f;
    f.id = 1;
    f.timestamp_ns = 1'699'999'999'123'456'789;
    char line[kMaxCandumpLineBytes];
    const size_t n = FormatCandumpLine(f, "can0", line);
    EXPECT_EQ(std::string(line, n), "(1699999999.123456) can0 001#\n");
}

TEST(CandumpWriter, AtomicFileAppearsOnlyOnClose) {
    test::TempDir dir;
    const auto path = dir / "log.candump";
    const Read read = ReadText(kCandumpLog);
    {
        CandumpWriter writer(path);
        for (size_t i = 0; i < read.frames.size(); ++i) {
            writer.Write(read.frames[i], read.interfaces[i]);
        }
        writer.Flush();
        EXPECT_FALSE(std::filesystem::exists(path));
        writer.Close();
        EXPECT_THROW(writer.Write(read.frames[0], "can0"), common::FileError);
    }
    ASSERT_TRUE(std::filesystem::exists(path));
    CandumpReader reader(path);
    EXPECT_EQ(WriteText(ReadAll(reader)), kCandumpLog);
    // Destroyed without Close: the old file stays, no temporary file is left behind.
    {
        CandumpWriter writer(path);
        writer.Write(read.frames[0], "can0");
        writer.Flush();
    }
    size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir.path())) {
        (void)e;
        ++files;
    }
    EXPECT_EQ(files, 1u);
    CandumpReader again(path);
    EXPECT_EQ(ReadAll(again).frames.size(), read.frames.size());
}

TEST(CandumpWriter, StreamingWritesWholeLines) {
    test::TempDir dir;
    const auto path = dir / "live.log";
    CandumpWriterConfig config;
    config.atomic = false;
    config.buffer_bytes = kMaxCandumpLineBytes;  // a flush nearly every line
    CanFrame f;
    f.id = 0x100;
    f.len = 8;
    {
        CandumpWriter writer(path, config);
        for (int i = 0; i < 1000; ++i) {
            f.timestamp_ns = int64_t{i} * 1000;
            writer.Write(f, "can0");
            if (i == 500) {
                // What is on disk is always a whole number of lines.
                std::string text;
                {
                    CandumpReader reader(path);
                    const Read r = ReadAll(reader);
                    EXPECT_FALSE(reader.truncated());
                    EXPECT_FALSE(r.stats.unterminated_last_line);
                    EXPECT_GT(r.frames.size(), 400u);
                }
            }
        }
    }  // the destructor flushes
    CandumpReader reader(path);
    EXPECT_EQ(ReadAll(reader).frames.size(), 1000u);
}

// Every kind of bad line: strict mode throws naming the file and the line; lenient mode skips it
// and counts it by cause.
TEST(CandumpBadLines, StrictThrowsLenientCounts) {
    struct Case {
        std::string line;
        CandumpIssue issue;
    };
    const std::vector<Case> cases = {
        {"garbage", CandumpIssue::kGarbage},
        {"1.5 can0 123#00", CandumpIssue::kGarbage},
        {"(1.5)can0 123#00", CandumpIssue::kGarbage},
        {"(1.5) can0 123#00 extra", CandumpIssue::kGarbage},
        {"(1.5) can0 123#00 R X", CandumpIssue::kGarbage},
        {"(1.5) can0 12300", CandumpIssue::kGarbage},
        {"(1.5) can0", CandumpIssue::kGarbage},
        {"(1.5)", CandumpIssue::kGarbage},
        {"(1.5) can0 123##", CandumpIssue::kGarbage},
        {"(1.5) can0 123#R1X", CandumpIssue::kGarbage},
        {"(abc.5) can0 123#00", CandumpIssue::kBadTimestamp},
        {"(15) can0 123#00", CandumpIssue::kBadTimestamp},
        {"(.5) can0 123#00", CandumpIssue::kBadTimestamp},
        {"(1.) can0 123#00", CandumpIssue::kBadTimestamp},
        {"(1.-5) can0 123#00", CandumpIssue::kBadTimestamp},
        {"(1.1234567890) can0 123#00", CandumpIssue::kBadTimestamp},
        {"(1.5 can0 123#00", CandumpIssue::kBadTimestamp},
        {"(9223372037.000000) can0 123#00", CandumpIssue::kBadTimestamp},
        {"(9223372036.854775808) can0 123#00", CandumpIssue::kBadTimestamp},
        {"(1.5) 123#00", CandumpIssue::kMissingInterface},
        {"(1.5) 123#00 R", CandumpIssue::kMissingInterface},
        {"(1.5) interface_too_long 123#00", CandumpIssue::kMissingInterface},
        {"(1.5) can0 12#00", CandumpIssue::kBadId},
        {"(1.5) can0 1234#00", CandumpIssue::kBadId},
        {"(1.5) can0 1G3#00", CandumpIssue::kBadId},
        {"(1.5) can0 800#00", CandumpIssue::kBadId},
        {"(1.5) can0 40000123#00", CandumpIssue::kBadId},
        {"(1.5) can0 A0000123#00", CandumpIssue::kBadId},
        {"(1.5) can0 20000080#R", CandumpIssue::kBadId},
        {"(1.5) can0 20000080##100", CandumpIssue::kBadId},
        {"(1.5) can0 123#00G1", CandumpIssue::kNonHex},
        {"(1.5) can0 123#0\x01", CandumpIssue::kNonHex},
        {"(1.5) can0 123##X00", CandumpIssue::kNonHex},
        {"(1.5) can0 123#RZ", CandumpIssue::kNonHex},
        {"(1.5) can0 123#1.1", CandumpIssue::kNonHex},
        {"(1.5) can0 123#001", CandumpIssue::kOddHex},
        {"(1.5) can0 123##1001", CandumpIssue::kOddHex},
        {"(1.5) can0 123#001122334455667788", CandumpIssue::kBadLength},
        {"(1.5) can0 123##1" + std::string(18, '0'), CandumpIssue::kBadLength},
        {"(1.5) can0 123##1" + std::string(130, '0'), CandumpIssue::kBadLength},
        {"(1.5) can0 123#R9", CandumpIssue::kBadLength},
        {"(1.5) can0 123#0011_C", CandumpIssue::kBadLength},
        {"(1.5) can0 123#0011223344556677_8", CandumpIssue::kBadLength},
        {"(1.5) can0 123#R4_C", CandumpIssue::kBadLength},
        {"(1.0) can0 123#00", CandumpIssue::kBackwards},
        {"(1.5) can0 " + std::string(5000, 'A'), CandumpIssue::kTooLong},
        {"(1.5) can0 12345###0012:34:56789ABC#00", CandumpIssue::kUnsupported},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.line.substr(0, 60));
        const std::string text = "(1.25) can0 100#01\n" + c.line + "\n(2.0) can0 101#02\n";
        // Strict: the first frame, then the error naming the file and line 2.
        CandumpReader strict = CandumpReader::FromMemory("bad.log", text);
        CandumpRecord r;
        ASSERT_TRUE(strict.Next(r));
        try {
            strict.Next(r);
            ADD_FAILURE() << "no error";
        } catch (const common::FileError& e) {
            EXPECT_EQ(e.path(), "bad.log");
            EXPECT_EQ(e.line(), 2u);
            EXPECT_NE(std::string(e.what()).find("bad.log:2: "), std::string::npos) << e.what();
        }
        // Lenient: both good frames, the bad line counted under its cause.
        const Read read = ReadText(text, CandumpMode::kLenient);
        ASSERT_EQ(read.frames.size(), 2u);
        EXPECT_EQ(read.lines[1], 3u);
        EXPECT_EQ(read.stats.skipped_by(c.issue), 1u) << ToString(c.issue);
        EXPECT_EQ(read.stats.skipped_lines(), 1u);
        EXPECT_EQ(read.stats.lines, 3u);
    }
}

TEST(CandumpBadLines, MessageSaysWhatAndShowsTheLine) {
    EXPECT_FILE_ERROR(
        {
            CandumpReader reader = CandumpReader::FromMemory("x.log", "(1.0) can0 123#001\n");
            CandumpRecord r;
            reader.Next(r);
        },
        "x.log", 1);
    try {
        CandumpReader reader = CandumpReader::FromMemory("x.log", "(1.0) can0 123#001\n");
        CandumpRecord r;
        reader.Next(r);
    } catch (const common::FileError& e) {
        EXPECT_EQ(std::string(e.what()),
                  "x.log:1: data with an odd number of hex digits: '(1.0) can0 123#001'");
    }
}

TEST(CandumpReader, BlankLinesAndEndings) {
    Read read = ReadText("\n(1.0) can0 123#00\r\n   \n\r\n(1.0) can0 123#01");
    ASSERT_EQ(read.frames.size(), 2u);
    EXPECT_EQ(read.stats.blank_lines, 3u);
    EXPECT_EQ(read.lines[1], 5u);
    EXPECT_TRUE(read.stats.unterminated_last_line);
    EXPECT_FALSE(read.truncated);
    // A cut last line (a killed candump): the end of the file, not an error, in strict mode too.
    read = ReadText("(1.0) can0 123#00\n(1.1) can0 123#0");
    EXPECT_EQ(read.frames.size(), 1u);
    EXPECT_TRUE(read.truncated);
    read = ReadText("(1.0) can0 123#00\n(1.1) ca");
    EXPECT_EQ(read.frames.size(), 1u);
    EXPECT_TRUE(read.truncated);
    read = ReadText("");
    EXPECT_TRUE(read.frames.empty());
    EXPECT_FALSE(read.truncated);
}

TEST(CandumpReader, EqualTimestampsAreInOrder) {
    const Read read = ReadText("(1.0) can0 123#00\n(1.0) can1 124#00\n(1.000000001) can0 125#\n");
    EXPECT_EQ(read.frames.size(), 3u);
}

TEST(CandumpReader, MissingFileAndFolder) {
    test::TempDir dir;
    EXPECT_FILE_ERROR(CandumpReader((dir / "missing.log")), (dir / "missing.log").string(), 0);
    EXPECT_FILE_ERROR(CandumpReader(dir.path()), dir.path().string(), 0);
}

TEST(CandumpReader, ConfigValidation) {
    CandumpReaderConfig config;
    config.max_line_bytes = 10;
    EXPECT_THROW(config.Validate(), common::Error);
    EXPECT_THROW(CandumpReader::FromMemory("x", "", config), common::Error);
    CandumpWriterConfig w;
    w.seconds_width = 0;
    EXPECT_THROW(w.Validate(), common::Error);
    w = {};
    w.interface_width = 16;
    EXPECT_THROW(w.Validate(), common::Error);
    w = {};
    w.buffer_bytes = 1;
    EXPECT_THROW(w.Validate(), common::Error);
}

void WriteGzip(const std::filesystem::path& path, const std::string& bytes) {
    gzFile gz = gzopen(path.c_str(), "wb");
    ASSERT_NE(gz, nullptr);
    ASSERT_EQ(gzwrite(gz, bytes.data(), static_cast<unsigned>(bytes.size())),
              static_cast<int>(bytes.size()));
    ASSERT_EQ(gzclose(gz), Z_OK);
}

// A long log: many buffer refills, lines across every buffer boundary.
std::string LongLog(size_t frames) {
    CandumpWriter writer(CandumpWriterConfig{});
    std::mt19937 rng(3);
    CanFrame f;
    for (size_t i = 0; i < frames; ++i) {
        f = CanFrame{};
        f.timestamp_ns = 1'600'000'000'000'000'000 + static_cast<int64_t>(i) * 1'000;
        f.fd = i % 7 == 0;
        f.extended = i % 3 == 0;
        f.id = static_cast<uint32_t>(rng() & (f.extended ? 0x1FFFFFFF : 0x7FF));
        f.len = static_cast<uint8_t>(f.fd ? 64 : i % 9);
        for (size_t k = 0; k < f.len; ++k) f.data[k] = static_cast<uint8_t>(rng());
        writer.Write(f, i % 2 ? "can0" : "vcan12");
    }
    return writer.text();
}

TEST(CandumpReader, GzipAndPlainFilesStream) {
    test::TempDir dir;
    const std::string text = LongLog(20000);
    ASSERT_GT(text.size(), 1'000'000u);
    test::WriteBytes(dir / "log.txt", text);
    WriteGzip(dir / "log.txt.gz", text);
    for (const char* name : {"log.txt", "log.txt.gz"}) {
        SCOPED_TRACE(name);
        CandumpReader reader(dir / name);
        const Read read = ReadAll(reader);
        EXPECT_EQ(read.frames.size(), 20000u);
        EXPECT_FALSE(read.truncated);
        EXPECT_EQ(WriteText(read), text);
    }
    // A gzip stream cut short: the frames before the cut, truncated(), no error.
    std::string gz;
    {
        std::ifstream in(dir / "log.txt.gz", std::ios::binary);
        gz.assign(std::istreambuf_iterator<char>(in), {});
    }
    test::WriteBytes(dir / "cut.gz", gz.substr(0, gz.size() / 2));
    CandumpReader cut(dir / "cut.gz");
    const Read read = ReadAll(cut);
    EXPECT_TRUE(read.truncated);
    EXPECT_GT(read.frames.size(), 1000u);
    EXPECT_LT(read.frames.size(), 20000u);
    // Broken gzip data: an error naming the file.
    std::string broken = gz;
    for (size_t i = gz.size() / 3; i < gz.size() / 3 + 64; ++i) broken[i] ^= 0x5A;
    test::WriteBytes(dir / "broken.gz", broken);
    CandumpReaderConfig lenient;
    lenient.mode = CandumpMode::kLenient;
    try {
        CandumpReader reader(dir / "broken.gz", lenient);
        ReadAll(reader);
        ADD_FAILURE() << "no error from broken gzip data";
    } catch (const common::FileError& e) {
        EXPECT_EQ(e.path(), (dir / "broken.gz").string());
    }
}

TEST(CandumpReader, OverlongLinesInAFileAreSkippedWithoutHoldingThem) {
    test::TempDir dir;
    const std::string text = "(1.0) can0 100#00\n" + std::string(300'000, 'x') +
                             "\n(2.0) can0 101#01\n" + std::string(100'000, 'y');
    test::WriteBytes(dir / "long.log", text);
    CandumpReaderConfig config;
    config.mode = CandumpMode::kLenient;
    CandumpReader reader(dir / "long.log", config);
    const Read read = ReadAll(reader);
    ASSERT_EQ(read.frames.size(), 2u);
    EXPECT_EQ(read.lines[1], 3u);
    EXPECT_EQ(read.stats.skipped_by(CandumpIssue::kTooLong), 2u);
    CandumpReader strict(dir / "long.log");
    CandumpRecord r;
    ASSERT_TRUE(strict.Next(r));
    EXPECT_FILE_ERROR(strict.Next(r), (dir / "long.log").string(), 2);
}

TEST(CandumpFuzz, MutatedLogsParseOrFailCleanly) {
    std::vector<test::FuzzSeed> seeds = {{kCandumpLog, 64}, {LongLog(20), 64}};
    size_t frames = 0;
    const auto counts = test::FuzzReader(
        "fuzz.log", seeds, 3000, 11, "0123456789ABCDEFabcdef#R_.() \n\r\t-\xff",
        [&](const std::string& bytes) {
            // Lenient: never throws on text in memory, and every frame it returns writes and
            // parses back to itself.
            CandumpReaderConfig lenient;
            lenient.mode = CandumpMode::kLenient;
            CandumpReader reader = CandumpReader::FromMemory("fuzz.log", bytes, lenient);
            CandumpRecord r;
            uint64_t skipped = 0;
            while (reader.Next(r)) {
                ++frames;
                char line[kMaxCandumpLineBytes];
                const size_t n = FormatCandumpLine(r.frame, r.interface_name, line);
                ASSERT_GT(n, 0u);
                CandumpLine again;
                CandumpIssue issue{};
                std::string_view what;
                ASSERT_TRUE(ParseCandumpLine(std::string_view(line, n - 1), again, issue, what));
                EXPECT_EQ(again.frame.timestamp_ns / 1000, r.frame.timestamp_ns / 1000);
                EXPECT_EQ(again.frame.id, r.frame.id);
                EXPECT_EQ(again.frame.len, r.frame.len);
                EXPECT_EQ(again.frame.data, r.frame.data);
                EXPECT_EQ(again.interface_name, r.interface_name);
            }
            skipped = reader.stats().skipped_lines();
            // Strict: the same frames up to the first bad line, then a FileError.
            CandumpReader strict = CandumpReader::FromMemory("fuzz.log", bytes);
            while (strict.Next(r)) {
            }
            EXPECT_EQ(skipped, 0u);  // reached only when strict accepted everything
        });
    EXPECT_GT(counts.accepted, 100u);
    EXPECT_GT(counts.rejected, 100u);
    EXPECT_GT(frames, 1000u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::can
