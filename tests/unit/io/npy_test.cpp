// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/npy.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <random>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::io {
namespace {
namespace BIMSLAM_UNITY_ID {
using common::Error;
using common::FileError;

template <typename T>
void ExpectRoundTrip(const std::vector<T>& values, std::vector<size_t> shape,
                     const std::string& dtype) {
    const NpyArray a = NpyArray::From(values.data(), shape);
    EXPECT_EQ(a.dtype, dtype);
    EXPECT_EQ(a.ItemSize(), sizeof(T));
    const std::string bytes = SerializeNpy(a);
    EXPECT_EQ(bytes.find('\n') + 1, bytes.size() - values.size() * sizeof(T));
    EXPECT_EQ((bytes.size() - values.size() * sizeof(T)) % 64, 0u) << "data not 64-aligned";
    const NpyArray b = ParseNpy("r.npy", bytes);
    EXPECT_EQ(b.dtype, dtype);
    EXPECT_EQ(b.shape, shape);
    ASSERT_EQ(b.ElementCount(), values.size());
    // Bytes, so that NaN and -0.0 count as equal to themselves.
    EXPECT_EQ(std::memcmp(b.As<T>(), values.data(), values.size() * sizeof(T)), 0) << dtype;
}

TEST(Npy, EveryDtypeRoundTrips) {
    ExpectRoundTrip<float>({1.5f, -0.0f, std::numeric_limits<float>::denorm_min(), 3e38f, 0.1f,
                            std::numeric_limits<float>::infinity()},
                           {2, 3}, "<f4");
    ExpectRoundTrip<double>({0.1, -1e300, std::nan("")}, {3}, "<f8");
    ExpectRoundTrip<uint8_t>({0, 255, 7, 9}, {2, 1, 2}, "|u1");
    ExpectRoundTrip<int8_t>({-128, 127}, {2}, "|i1");
    ExpectRoundTrip<uint16_t>({0, 65535}, {1, 2}, "<u2");
    ExpectRoundTrip<int16_t>({-32768, 32767}, {2}, "<i2");
    ExpectRoundTrip<uint32_t>({0, 4294967295u}, {2}, "<u4");
    ExpectRoundTrip<int32_t>({std::numeric_limits<int32_t>::min(), 5}, {2}, "<i4");
    ExpectRoundTrip<uint64_t>({std::numeric_limits<uint64_t>::max(), 1}, {2}, "<u8");
    ExpectRoundTrip<int64_t>({std::numeric_limits<int64_t>::min(), -1}, {2}, "<i8");
    const bool flags[] = {true, false, true};
    const NpyArray b = ParseNpy("b.npy", SerializeNpy(NpyArray::From(flags, {3})));
    EXPECT_EQ(b.dtype, "|b1");
    EXPECT_TRUE(b.As<bool>()[0] && !b.As<bool>()[1] && b.As<bool>()[2]);
    // 0-d and empty arrays.
    const double pi = 3.25;
    const NpyArray scalar = ParseNpy("s.npy", SerializeNpy(NpyArray::From(&pi, {})));
    EXPECT_TRUE(scalar.shape.empty());
    EXPECT_EQ(scalar.As<double>()[0], 3.25);
    const NpyArray empty = ParseNpy("e.npy", SerializeNpy(NpyArray::From<float>(nullptr, {0, 4})));
    EXPECT_EQ(empty.shape, (std::vector<size_t>{0, 4}));
    EXPECT_TRUE(empty.data.empty());
}

TEST(Npy, WritesWhatNumpySaveWrites) {
    // np.save(f, np.arange(6, dtype='<f4').reshape(2, 3)) with numpy 1.24.
    const float v[] = {0, 1, 2, 3, 4, 5};
    const std::string bytes = SerializeNpy(NpyArray::From(v, {2, 3}));
    std::string header("\x93NUMPY\x01\x00\x76\x00", 10);
    header += "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }";
    header.append(128 - 1 - header.size(), ' ');
    header += '\n';
    EXPECT_EQ(bytes.substr(0, 128), header);
    const uint8_t u[] = {1};
    EXPECT_NE(SerializeNpy(NpyArray::From(u, {1})).find("'shape': (1,), }"), std::string::npos);
    test::TempDir dir;
    WriteNpy(dir / "a.npy", NpyArray::From(v, {6}));
    EXPECT_EQ(ReadNpy(dir / "a.npy").shape, std::vector<size_t>{6});
}

TEST(Npy, ReadsVersions2And3AndOtherSpellings) {
    const std::string dict = "{\"shape\": (2L, 1), \"fortran_order\": False, 'descr': '<u1',}\n";
    for (char major : {'\x02', '\x03'}) {
        std::string f("\x93NUMPY", 6);
        f += major;
        f += '\0';
        const uint32_t len = static_cast<uint32_t>(dict.size());
        f.append(reinterpret_cast<const char*>(&len), 4);
        f += dict + "\x05\x06";
        const NpyArray a = ParseNpy("v.npy", f);
        EXPECT_EQ(a.dtype, "|u1");  // '<' on a 1-byte type means the same as '|'
        EXPECT_EQ(a.shape, (std::vector<size_t>{2, 1}));
        EXPECT_EQ(a.As<uint8_t>()[1], 6);
    }
}

std::string Npy1(const std::string& dict, const std::string& data) {
    std::string f("\x93NUMPY\x01\x00", 8);
    f += static_cast<char>(dict.size() & 0xff);
    f += static_cast<char>(dict.size() >> 8);
    return f + dict + data;
}

TEST(Npy, RejectsBadFilesNamingThem) {
    const std::string ok = "{'descr': '<i2', 'fortran_order': False, 'shape': (2,), }\n";
    EXPECT_EQ(ParseNpy("ok.npy", Npy1(ok, std::string("\x01\x00\x02\x00", 4))).As<int16_t>()[1], 2);
    EXPECT_FILE_ERROR(ParseNpy("e.npy", ""), "e.npy", 0);
    EXPECT_FILE_ERROR(ParseNpy("g.npy", "PK\x03\x04 not numpy at all"), "g.npy", 0);
    EXPECT_FILE_ERROR(ParseNpy("t.npy", std::string("\x93NUMPY\x01", 7)), "t.npy", 0);
    std::string v4 = Npy1(ok, std::string("\x01\x00\x02\x00", 4));
    v4[6] = 4;
    EXPECT_FILE_ERROR(ParseNpy("v.npy", v4), "v.npy", 0);
    const std::string good = Npy1(ok, std::string("\x01\x00\x02\x00", 4));
    EXPECT_FILE_ERROR(ParseNpy("h.npy", good.substr(0, 30)), "h.npy", 0);
    EXPECT_FILE_ERROR(ParseNpy("d.npy", good.substr(0, good.size() - 1)), "d.npy", 0);
    EXPECT_FILE_ERROR(ParseNpy("d.npy", good + "x"), "d.npy", 0);
    const std::string data(4, '\0');
    for (const char* dict : {
             "{'descr': '<i2', 'fortran_order': True, 'shape': (2,), }",
             "{'descr': '>i2', 'fortran_order': False, 'shape': (2,), }",
             "{'descr': '|O', 'fortran_order': False, 'shape': (2,), }",
             "{'descr': '<c8', 'fortran_order': False, 'shape': (2,), }",
             "{'descr': [('a', '<i2')], 'fortran_order': False, 'shape': (2,), }",
             "{'descr': '<i2', 'fortran_order': False, 'shape': (2), }",
             "{'descr': '<i2', 'fortran_order': False, 'shape': (-2,), }",
             "{'descr': '<i2', 'fortran_order': False, 'shape': (2,), 'x': 1}",
             "{'descr': '<i2', 'fortran_order': False}",
             "{'descr': '<i2', 'descr': '<i2', 'fortran_order': False, 'shape': (2,)}",
             "{'descr': '<i2', 'fortran_order': Nope, 'shape': (2,), }",
             "{'descr': '<i2, 'fortran_order': False, 'shape': (2,), }",
             "{'descr': '<i2', 'fortran_order': False, 'shape': (2,), } junk",
             "{'descr': '<i2', 'fortran_order': False, 'shape': (99999999999999999999,), }",
             "{'descr': '<i2', 'fortran_order': False, 'shape': (4294967296, 4294967296), }",
             "{'descr': '<i2', 'fortran_order': False, 'shape': (1, 2, 3, 4, 5, 6, 7, 8, 9, 0, "
             "1, 2, 3, 4, 5, 6, 7, 8, 9, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 0, 1, 2, 3, 4, 5, 6, 7, 8, "
             "9, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 0, 1, 2, 3, 4, 5), }",
         }) {
        EXPECT_FILE_ERROR(ParseNpy("m.npy", Npy1(dict, data)), "m.npy", 0);
    }
    // bool bytes must be 0 or 1: anything else is not a valid bool to view.
    const std::string b = "{'descr': '|b1', 'fortran_order': False, 'shape': (2,), }";
    EXPECT_FILE_ERROR(ParseNpy("b.npy", Npy1(b, std::string("\x01\x02", 2))), "b.npy", 0);
    EXPECT_FILE_ERROR(ReadNpy("/nonexistent/a.npy"), "/nonexistent/a.npy", 0);
}

TEST(Npy, TypedViewsAndWriterCheckTheirArguments) {
    const float v[] = {1, 2};
    NpyArray a = NpyArray::From(v, {2});
    EXPECT_THROW(a.As<double>(), Error);
    EXPECT_THROW(a.As<int32_t>(), Error);
    EXPECT_THROW(NpyArray::From<float>(nullptr, {2}), Error);
    test::TempDir dir;
    const std::string path = (dir / "w.npy").string();
    a.data.pop_back();
    EXPECT_THROW(a.As<float>(), Error);
    EXPECT_FILE_ERROR(WriteNpy(path, a), path, 0);
    a = NpyArray::From(v, {2});
    a.dtype = "<f2";
    EXPECT_FILE_ERROR(WriteNpy(path, a), path, 0);
    EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(Npy, MutatedFilesOnlyEverThrowFileError) {
    const int32_t v[] = {1, -2, 3, -4, 5, -6};
    const bool flags[] = {true, false};
    const std::vector<test::FuzzSeed> seeds = {{SerializeNpy(NpyArray::From(v, {3, 2})), 128},
                                               {SerializeNpy(NpyArray::From(flags, {2})), 128}};
    const char interesting[] = "0123456789 ,()'\"{}:<|fiub-L\x00\xff";
    const auto [parsed, rejected] =
        test::FuzzReader("fuzz.npy", seeds, 3000, 11, {interesting, sizeof(interesting) - 1},
                         [](const std::string& b) { ParseNpy("fuzz.npy", b); });
    EXPECT_GT(rejected, 1000u);
    EXPECT_GT(parsed, 10u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::io
