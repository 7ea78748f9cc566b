// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/text_reader.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/io/file_util.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::io {
namespace {
namespace BIMSLAM_UNITY_ID {
using common::FileError;

TEST(LineReader, LinesNumbersAndCrlf) {
    LineReader r("f.txt", "a b\r\n\nc\n  d  ");
    std::string_view line;
    ASSERT_TRUE(r.Next(line));
    EXPECT_EQ(line, "a b");
    EXPECT_EQ(r.line_number(), 1u);
    ASSERT_TRUE(r.Next(line));
    EXPECT_EQ(line, "");
    ASSERT_TRUE(r.Next(line));
    EXPECT_EQ(line, "c");
    ASSERT_TRUE(r.Next(line));
    EXPECT_EQ(r.line_number(), 4u);
    std::vector<std::string_view> tok;
    LineReader::Split(line, tok);
    ASSERT_EQ(tok.size(), 1u);
    EXPECT_EQ(tok[0], "d");
    EXPECT_FALSE(r.Next(line));
}

TEST(LineReader, NumbersAreCheckedAndErrorsNameFileAndLine) {
    LineReader r("poses.txt", "x\ny\n");
    std::string_view line;
    r.Next(line);
    r.Next(line);
    EXPECT_DOUBLE_EQ(r.ParseDouble("+1.5e3", "x"), 1500.0);
    EXPECT_EQ(r.ParseInt("-42", "n"), -42);
    for (const char* bad : {"abc", "1.5x", "", "nan", "inf", "-inf", "1e999"}) {
        try {
            r.ParseDouble(bad, "qx");
            ADD_FAILURE() << "accepted '" << bad << "'";
        } catch (const FileError& e) {
            EXPECT_EQ(e.path(), "poses.txt");
            EXPECT_EQ(e.line(), 2u);
            EXPECT_NE(std::string(e.what()).find("qx"), std::string::npos) << e.what();
        }
    }
    EXPECT_THROW(r.ParseInt("1.5", "n"), FileError);
    EXPECT_THROW(r.ParseInt("99999999999999999999", "n"), FileError);
}

TEST(LineReader, SecondsParseExactlyToNanoseconds) {
    LineReader r("t", "");
    EXPECT_EQ(r.ParseSecondsToNs("1699999999.123456789", "t"), 1'699'999'999'123'456'789);
    EXPECT_EQ(r.ParseSecondsToNs("1305031102.175304", "t"), 1'305'031'102'175'304'000);
    EXPECT_EQ(r.ParseSecondsToNs("12", "t"), 12'000'000'000);
    EXPECT_EQ(r.ParseSecondsToNs("0.0000000015", "t"), 2);  // rounded on the tenth digit
    EXPECT_EQ(r.ParseSecondsToNs("-1.5", "t"), -1'500'000'000);
    EXPECT_EQ(r.ParseSecondsToNs("1.5e9", "t"), 1'500'000'000'000'000'000);
    EXPECT_THROW(r.ParseSecondsToNs("1.2.3", "t"), FileError);
    EXPECT_THROW(r.ParseSecondsToNs("99999999999", "t"), FileError);
    for (int64_t ns : {int64_t{0}, int64_t{1}, int64_t{-1}, int64_t{1'699'999'999'000'000'001},
                       int64_t{-1'500'000'000}}) {
        EXPECT_EQ(r.ParseSecondsToNs(FormatNsAsSeconds(ns), "t"), ns) << ns;
    }
}

TEST(FileUtil, AtomicWriteReplacesAndLeavesNoTemporary) {
    test::TempDir dir;
    const auto path = dir / "a.txt";
    WriteFileAtomic(path, "one");
    WriteFileAtomic(path, "two");
    EXPECT_EQ(ReadFileToString(path), "two");
    size_t files = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++files;
    EXPECT_EQ(files, 1u);
    try {
        ReadFileToString(dir / "missing.txt");
        ADD_FAILURE();
    } catch (const FileError& e) {
        EXPECT_EQ(e.code(), common::StatusCode::kNotFound);
        EXPECT_NE(std::string(e.what()).find("missing.txt"), std::string::npos);
    }
    EXPECT_THROW(WriteFileAtomic(dir / "no" / "such" / "dir.txt", "x"), FileError);
}

// The piecewise form (large files, LAS): the pieces in order; a producer that throws leaves the
// old file as it was and no temporary.
TEST(FileUtil, AtomicWriteInPieces) {
    test::TempDir dir;
    const auto path = dir / "p.bin";
    const std::vector<std::string> pieces = {"head", std::string(100000, 'x'), "tail"};
    size_t k = 0;
    WriteFileAtomic(path, [&]() { return k < pieces.size() ? std::string_view(pieces[k++]) : ""; });
    EXPECT_EQ(ReadFileToString(path), pieces[0] + pieces[1] + pieces[2]);
    k = 0;
    EXPECT_THROW(WriteFileAtomic(path,
                                 [&]() -> std::string_view {
                                     if (k++ == 1) throw std::runtime_error("producer failed");
                                     return "new";
                                 }),
                 std::runtime_error);
    EXPECT_EQ(ReadFileToString(path), pieces[0] + pieces[1] + pieces[2]);
    size_t files = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++files;
    EXPECT_EQ(files, 1u);
}

// Past the page cache (O_DIRECT, LAS): pieces of sizes that cross the 4096-byte blocks and the
// 8 MiB staging buffer come back in order, byte for byte, with the last partial block; a file
// of no bytes; a throwing producer keeps the old file. /dev/shm (tmpfs) too, where the kernel
// may refuse O_DIRECT and the page cache serves.
TEST(FileUtil, AtomicWriteInPiecesPastThePageCache) {
    std::vector<std::string> pieces;
    uint32_t k = 0;
    for (const size_t size : {size_t(1), size_t(4095), (size_t(8) << 20) + 3, size_t(5),
                              size_t(3) << 20, size_t(4096)}) {
        std::string piece(size, '\0');
        for (char& c : piece) c = char((k++ * 2654435761u) >> 24);  // no period of 4096
        pieces.push_back(std::move(piece));
    }
    std::string all;
    for (const std::string& p : pieces) all += p;
    test::TempDir tmp;
    std::vector<std::filesystem::path> dirs = {tmp.path()};
    if (std::filesystem::is_directory("/dev/shm")) dirs.push_back("/dev/shm");
    for (const std::filesystem::path& dir : dirs) {
        SCOPED_TRACE(dir.string());
        const auto path = dir / ("bimslam_direct_" + std::to_string(::getpid()) + ".bin");
        size_t i = 0;
        const auto next = [&]() { return i < pieces.size() ? std::string_view(pieces[i++]) : ""; };
        WriteFileAtomic(path, next, Sync::kNow, Cache::kBypass);
        EXPECT_TRUE(ReadFileToString(path) == all);
        EXPECT_THROW(WriteFileAtomic(
                         path, [&]() -> std::string_view { throw std::runtime_error("failed"); },
                         Sync::kNow, Cache::kBypass),
                     std::runtime_error);
        EXPECT_TRUE(ReadFileToString(path) == all);
        WriteFileAtomic(
            path, []() { return std::string_view(); }, Sync::kNow, Cache::kBypass);
        EXPECT_EQ(std::filesystem::file_size(path), 0u);
        std::filesystem::remove(path);
    }
}

// A session's line files grow by appends. One that fails part-way (here the file-size limit of
// setrlimit(2), which lets a write in up to the limit and refuses the rest with EFBIG, as a full
// disk does) is cut back off the file: the next append follows the last whole one, never half a
// line.
TEST(FileUtil, AppendFileGrowsAndCutsAFailedAppendBackOff) {
    test::TempDir dir;
    const auto path = dir / "lines.txt";
    WriteFileAtomic(path, "an old file\n");
    AppendFile f(path);
    EXPECT_EQ(ReadFileToString(path), "");  // a new file starts empty
    f.Append("one\n", Sync::kNow);
    f.Append("two\n", Sync::kDeferred);
    EXPECT_EQ(ReadFileToString(path), "one\ntwo\n");
    EXPECT_EQ(f.size(), 8u);

    rlimit old{};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
    void (*old_handler)(int) = std::signal(SIGXFSZ, SIG_IGN);
    rlimit small = old;
    small.rlim_cur = 12;  // room for 4 of the 8 bytes below
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
    std::string error;
    try {
        f.Append("three3\n", Sync::kNow);
    } catch (const FileError& e) {
        error = e.what();
    }
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &old), 0);
    std::signal(SIGXFSZ, old_handler);
    EXPECT_NE(error.find("lines.txt"), std::string::npos) << error;
    EXPECT_NE(error.find("cannot append"), std::string::npos) << error;
    EXPECT_EQ(ReadFileToString(path), "one\ntwo\n");
    f.Append("four\n", Sync::kNow);
    EXPECT_EQ(ReadFileToString(path), "one\ntwo\nfour\n");
    EXPECT_THROW(AppendFile(dir / "no" / "such" / "dir.txt"), FileError);
}

TEST(FileUtil, FormatIsShortestExact) {
    for (double v : {0.1, 1.0 / 3.0, -2.5e-300, 1e21, 123456789.125}) {
        EXPECT_EQ(std::stod(FormatDouble(v)), v);
    }
    EXPECT_EQ(FormatDouble(0.1), "0.1");
    EXPECT_EQ(FormatFloat(0.1f), "0.1");
    EXPECT_EQ(std::stof(FormatFloat(1.0f / 3.0f)), 1.0f / 3.0f);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::io
