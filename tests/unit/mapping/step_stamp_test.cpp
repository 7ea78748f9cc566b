// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// StepStamp: what decides whether `bimslam map` re-runs a step. A stamp matches its own file, and
// stops matching when an input's content (by SHA-256), size or mtime, an upstream stamp or a
// parameter changes; a missing, damaged or foreign file never matches. CheckModelFile refuses
// what is not IFC.
#include "host_tools/mapping/step_stamp.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "host_tools/mapping/map_inputs.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::mapping {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;

TEST(StepStamp, MatchesItselfAndNotAChangedInputUpstreamOrParameter) {
    test::TempDir tmp;
    io::WriteFileAtomic(tmp / "model.ifc", "model v1");
    io::WriteFileAtomic(tmp / "lidar.pcap", "packets");
    auto make = [&](double budget) {
        StepStamp s("odometry");
        s.AddFileContent("model", tmp / "model.ifc");
        s.AddFileTime("pcap", tmp / "lidar.pcap");
        s.AddParameter("budget_ms", budget);
        return s;
    };
    StepStamp a = make(50);
    a.MarkMade();
    a.Write(tmp / "stamp.json");
    EXPECT_TRUE(make(50).Matches(tmp / "stamp.json"));
    EXPECT_FALSE(make(60).Matches(tmp / "stamp.json")) << "a parameter";
    EXPECT_NE(make(60).Digest(), make(50).Digest());

    // The model by content: rewritten with the same bytes it still matches.
    io::WriteFileAtomic(tmp / "model.ifc", "model v1");
    EXPECT_TRUE(make(50).Matches(tmp / "stamp.json"));
    io::WriteFileAtomic(tmp / "model.ifc", "model v2");
    EXPECT_FALSE(make(50).Matches(tmp / "stamp.json")) << "the model's content";
    io::WriteFileAtomic(tmp / "model.ifc", "model v1");

    // The recording by size and mtime: touched, it does not.
    const auto t = fs::last_write_time(tmp / "lidar.pcap");
    fs::last_write_time(tmp / "lidar.pcap", t + std::chrono::seconds(1));
    EXPECT_FALSE(make(50).Matches(tmp / "stamp.json")) << "the recording touched";
    fs::last_write_time(tmp / "lidar.pcap", t);
    EXPECT_TRUE(make(50).Matches(tmp / "stamp.json"));

    // Upstream: a downstream stamp holds the upstream's digest, made token included: a stamp
    // that matched its file takes the file's token, so it digests as the one written.
    StepStamp down("anchor");
    down.AddUpstream(a);
    down.MarkMade();
    down.Write(tmp / "down.json");
    StepStamp again = make(50);
    ASSERT_TRUE(again.Matches(tmp / "stamp.json"));
    EXPECT_EQ(again.Digest(), a.Digest());
    StepStamp down_again("anchor");
    down_again.AddUpstream(again);
    EXPECT_TRUE(down_again.Matches(tmp / "down.json"));
    // The upstream ran again with the same inputs (a new token): the downstream is out of date.
    StepStamp rerun = make(50);
    rerun.MarkMade();
    StepStamp down_rerun("anchor");
    down_rerun.AddUpstream(rerun);
    EXPECT_FALSE(down_rerun.Matches(tmp / "down.json"));
}

TEST(StepStamp, AMissingDamagedOrForeignFileDoesNotMatch) {
    test::TempDir tmp;
    StepStamp s("report");
    s.AddFileTime("absent", tmp / "absent.json");  // noted as missing: appearing changes it
    EXPECT_TRUE(s.json()["inputs"]["absent"]["missing"].get<bool>());
    EXPECT_FALSE(s.Matches(tmp / "stamp.json"));
    io::WriteFileAtomic(tmp / "stamp.json", "{\"format\": ");
    EXPECT_FALSE(s.Matches(tmp / "stamp.json"));
    io::WriteFileAtomic(tmp / "stamp.json", "[1, 2]\n");
    EXPECT_FALSE(s.Matches(tmp / "stamp.json"));
    s.Write(tmp / "stamp.json");
    EXPECT_FALSE(s.Matches(tmp / "stamp.json")) << "never made: not a finished step's stamp";
    s.MarkMade();
    s.Write(tmp / "stamp.json");
    EXPECT_TRUE(s.Matches(tmp / "stamp.json"));
}

// The program that made a step: this test program's GNU build ID (Debian's linker writes one),
// matched by its stamp; another build's stamp, or one naming none, still matches (the step is
// kept) but says so, and the digest the steps after it hold is the same.
TEST(StepStamp, NamesTheProgramThatMadeItAndKeepsAnotherBuildsStepSayingSo) {
    test::TempDir tmp;
    const std::string& program = StepStamp::Program();
    ASSERT_EQ(program.rfind("build-id ", 0), 0u) << program;
    EXPECT_EQ(program.size(), std::string("build-id ").size() + 40) << "SHA-1: 20 bytes in hex";
    const auto readelf =
        test::RunCommand("readelf -n /proc/" + std::to_string(::getpid()) + "/exe");
    if (readelf.exit_code == 0) {
        EXPECT_NE(readelf.out.find("Build ID: " + program.substr(9)), std::string::npos)
            << readelf.out;
    }
    StepStamp made("changes");
    made.AddParameter("tolerance_m", 0.01);
    made.MarkMade();
    EXPECT_EQ(made.json().at("program"), program);
    made.Write(tmp / "stamp.json");
    StepStamp now("changes");
    now.AddParameter("tolerance_m", 0.01);
    ASSERT_TRUE(now.Matches(tmp / "stamp.json"));
    EXPECT_TRUE(now.MadeByThisProgram());
    for (const nlohmann::json& other : {nlohmann::json("build-id 0123"), nlohmann::json()}) {
        nlohmann::json j = made.json();
        if (other.is_null()) {
            j.erase("program");  // a stamp of before the program was named
        } else {
            j["program"] = other;
        }
        io::WriteFileAtomic(tmp / "stamp.json", j.dump(2));
        StepStamp again("changes");
        again.AddParameter("tolerance_m", 0.01);
        ASSERT_TRUE(again.Matches(tmp / "stamp.json")) << j.dump();
        EXPECT_FALSE(again.MadeByThisProgram()) << j.dump();
        EXPECT_EQ(again.Digest(), made.Digest()) << "the steps after it stay up to date";
    }
}

TEST(MapInputs, AModelThatIsNotIfcIsRefusedNamingTheFile) {
    test::TempDir tmp;
    auto refused = [&](const std::string& text) {
        io::WriteFileAtomic(tmp / "m.ifc", text);
        try {
            CheckModelFile(tmp / "m.ifc");
        } catch (const common::FileError& e) {
            EXPECT_EQ(e.path(), (tmp / "m.ifc").string());
            return true;
        }
        return false;
    };
    EXPECT_TRUE(refused(""));
    EXPECT_TRUE(refused("solid x\nendsolid x\n"));
    EXPECT_TRUE(refused("ISO-10303-21;\nHEADER;\nFILE_SCHEMA(('AP214'));\nENDSEC;\n"));
    EXPECT_FALSE(refused("ISO-10303-21;\nHEADER;\nFILE_SCHEMA(('IFC4'));\nENDSEC;\n"));
    EXPECT_FALSE(refused("\xEF\xBB\xBF ISO-10303-21;\nHEADER;\nFILE_SCHEMA (('IFC2X3'));\n"));
    EXPECT_THROW(CheckModelFile(tmp / "absent.ifc"), common::FileError);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::mapping
