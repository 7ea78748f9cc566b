// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/session.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <random>

#include "algorithms/common/se3.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/g2o.hpp"
#include "algorithms/io/text_reader.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::io {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;
using common::FileError;

SessionManifest Manifest() {
    SessionManifest m;
    m.source = "rig";
    m.descriptor.rings = 4;
    m.descriptor.sectors = 6;
    m.descriptor.min_points = 3;
    m.descriptor.min_z_span_m = 0.3;
    return m;
}

SessionKeyframe MakeKeyframe(size_t i, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    SessionKeyframe kf;
    kf.stamp_ns = 1'700'000'000'000'000'000 + static_cast<int64_t>(i) * 1'000'000'123;
    common::Vector6d xi;
    for (int k = 0; k < 6; ++k) xi[k] = u(rng) * (k < 3 ? 10.0 : 1.0);
    kf.T_world_lidar = common::ExpSE3(xi);
    kf.T_odom_lidar = common::ExpSE3(0.9 * xi);
    kf.descriptor = DescriptorMatrix::NullaryExpr(4, 6, [&] { return float(u(rng) + 1.0); });
    kf.cloud = test::MakeRoomScan(4, 32, static_cast<uint32_t>(i));
    return kf;
}

struct Written {
    std::vector<SessionKeyframe> keyframes;
    std::vector<SessionEdge> edges;
    std::vector<StampedPose> trajectory;
};

// Writes n keyframes, an odometry edge between consecutive ones, three scan poses per keyframe.
Written WriteSession(const fs::path& dir, size_t n, bool finish,
                     SessionWriterOptions options = {}) {
    std::mt19937 rng(42);
    Written w;
    SessionWriter writer(dir, Manifest(), options);
    for (size_t i = 0; i < n; ++i) {
        w.keyframes.push_back(MakeKeyframe(i, rng));
        for (int s = 0; s < 3; ++s) {
            w.trajectory.push_back(StampedPose::FromIsometry(
                w.keyframes.back().stamp_ns + s * 100'000'000, w.keyframes.back().T_world_lidar));
            writer.AddScanPose(w.trajectory.back());
        }
        EXPECT_EQ(writer.AddKeyframe(w.keyframes.back()), i);
        if (i > 0) {
            SessionEdge e;
            e.from = static_cast<uint32_t>(i - 1);
            e.to = static_cast<uint32_t>(i);
            e.T_from_to =
                common::Between(w.keyframes[i - 1].T_world_lidar, w.keyframes[i].T_world_lidar);
            e.information = common::Matrix6d::Identity() * (100.0 + double(i));
            e.information(0, 5) = e.information(5, 0) = 0.25;
            writer.AddEdge(e);
            w.edges.push_back(e);
        }
    }
    if (finish) writer.Finish();
    return w;
}

// Replaces line `line_index` (0-based) of a file, or deletes it when new_line is empty.
void ReplaceInFile(const fs::path& path, size_t line_index, const std::string& new_line) {
    std::string text = ReadFileToString(path), out;
    size_t line = 0, start = 0;
    while (start < text.size()) {
        const size_t end = text.find('\n', start);
        const std::string l = text.substr(start, end - start);
        if (line != line_index) {
            out += l + "\n";
        } else if (!new_line.empty()) {
            out += new_line + "\n";
        }
        ++line;
        start = end == std::string::npos ? text.size() : end + 1;
    }
    test::WriteBytes(path, out);
}

TEST(Session, RoundTripIsBitExact) {
    test::TempDir tmp;
    const fs::path dir = tmp / "s";
    const Written w = WriteSession(dir, 12, true);
    const Session s = ReadSession(dir);
    EXPECT_TRUE(s.complete);
    EXPECT_TRUE(s.notes.empty());
    EXPECT_EQ(s.manifest.source, "rig");
    EXPECT_EQ(s.manifest.counts.keyframes, 12u);
    EXPECT_EQ(s.manifest.counts.scans, 36u);
    EXPECT_EQ(s.manifest.descriptor.min_points, 3);
    EXPECT_FALSE(s.manifest.created.empty());
    ASSERT_EQ(s.keyframes.size(), 12u);
    for (size_t i = 0; i < 12; ++i) {
        const SessionKeyframe& a = w.keyframes[i];
        const SessionKeyframe& b = s.keyframes[i];
        EXPECT_EQ(a.stamp_ns, b.stamp_ns);
        EXPECT_EQ(a.T_world_lidar.matrix(), b.T_world_lidar.matrix());
        ASSERT_TRUE(b.T_odom_lidar.has_value());
        EXPECT_EQ(a.T_odom_lidar->matrix(), b.T_odom_lidar->matrix());
        EXPECT_EQ(a.descriptor, b.descriptor);
        ASSERT_EQ(a.cloud.size(), b.cloud.size());
        EXPECT_EQ(a.cloud.xyz, b.cloud.xyz);
        EXPECT_EQ(a.cloud.intensity, b.cloud.intensity);
        EXPECT_EQ(a.cloud.ring, b.cloud.ring);
        EXPECT_EQ(b.cloud.stamp.ns, a.stamp_ns);
    }
    ASSERT_EQ(s.edges.size(), w.edges.size());
    for (size_t i = 0; i < w.edges.size(); ++i) {
        EXPECT_EQ(s.edges[i].from, w.edges[i].from);
        EXPECT_EQ(s.edges[i].to, w.edges[i].to);
        EXPECT_EQ(s.edges[i].information, w.edges[i].information);
        EXPECT_LT((s.edges[i].T_from_to.matrix() - w.edges[i].T_from_to.matrix()).norm(), 1e-12);
    }
    ASSERT_EQ(s.trajectory.size(), w.trajectory.size());
    EXPECT_EQ(SerializeTum(s.trajectory), SerializeTum(w.trajectory));
}

TEST(Session, DeferredSyncWritesTheSameSession) {
    test::TempDir tmp;
    const Written w = WriteSession(tmp / "now", 7, true);
    WriteSession(tmp / "later", 7, true, {.flush_every = 3, .sync_each_file = false});
    const Session a = ReadSession(tmp / "now");
    const Session b = ReadSession(tmp / "later");
    ASSERT_TRUE(b.complete);
    ASSERT_EQ(b.keyframes.size(), w.keyframes.size());
    for (size_t i = 0; i < b.keyframes.size(); ++i) {
        EXPECT_EQ(a.keyframes[i].cloud.xyz, b.keyframes[i].cloud.xyz);
        EXPECT_EQ(a.keyframes[i].descriptor, b.keyframes[i].descriptor);
        EXPECT_EQ(a.keyframes[i].T_world_lidar.matrix(), b.keyframes[i].T_world_lidar.matrix());
    }
    for (const char* f :
         {"times.txt", "optimized_poses.txt", "singlesession_posegraph.g2o", "trajectory.tum"}) {
        EXPECT_EQ(ReadFileToString(tmp / "now" / f), ReadFileToString(tmp / "later" / f)) << f;
    }
    // No temporary file is left behind.
    for (const auto& e : fs::recursive_directory_iterator(tmp / "later")) {
        EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
    }
}

// The writer formats each item once, as it is added, and a flush appends the text added since
// the last one: the files must be what formatting the whole session at once gives (the writer
// before did that at every flush), the pose graph's lines in the order they were added (an edge
// after the keyframes it joins).
TEST(Session, EachFileIsTheWholeSessionFormattedAtOnce) {
    test::TempDir tmp;
    const Written w = WriteSession(tmp / "s", 9, true);
    std::string times, graph;
    std::vector<Eigen::Isometry3d> world, odom;
    for (size_t i = 0; i < w.keyframes.size(); ++i) {
        const SessionKeyframe& k = w.keyframes[i];
        times += FormatNsAsSeconds(k.stamp_ns) + "\n";
        world.push_back(k.T_world_lidar);
        odom.push_back(*k.T_odom_lidar);
        AppendG2oVertex(graph, i, k.T_world_lidar);  // SerializeG2o's lines, in adding order
        if (i > 0) AppendG2oEdge(graph, w.edges[i - 1]);
    }
    EXPECT_EQ(ReadFileToString(tmp / "s" / "times.txt"), times);
    EXPECT_EQ(ReadFileToString(tmp / "s" / "optimized_poses.txt"), SerializeKitti(world));
    EXPECT_EQ(ReadFileToString(tmp / "s" / "odom_poses.txt"), SerializeKitti(odom));
    EXPECT_EQ(ReadFileToString(tmp / "s" / "singlesession_posegraph.g2o"), graph);
    EXPECT_EQ(ReadFileToString(tmp / "s" / "trajectory.tum"), SerializeTum(w.trajectory));
}

// A rig session is written for hours: the writer keeps only the text since its last flush, and
// a flush appends it (the files keep their inode: nothing rewritten whole).
TEST(Session, TheWriterHoldsOnlyWhatCameSinceItsLastFlush) {
    test::TempDir tmp;
    const fs::path dir = tmp / "s";
    std::mt19937 rng(7);
    SessionWriter writer(dir, Manifest(), {.flush_every = 1000});
    writer.Flush();
    const auto inode = [&](const char* f) {
        struct stat st {};
        EXPECT_EQ(::stat((dir / f).c_str(), &st), 0) << f;
        return st.st_ino;
    };
    const ino_t trajectory = inode("trajectory.tum"), graph = inode("singlesession_posegraph.g2o");
    EXPECT_EQ(writer.pending_bytes(), 0u);
    for (int i = 0; i < 200; ++i) {
        writer.AddScanPose(
            StampedPose::FromIsometry(int64_t(i) * 100'000'000, Eigen::Isometry3d::Identity()));
    }
    writer.AddKeyframe(MakeKeyframe(0, rng));
    const size_t pending = writer.pending_bytes();
    EXPECT_GT(pending, 200u * 20);
    writer.Flush();
    EXPECT_EQ(writer.pending_bytes(), 0u);
    EXPECT_EQ(fs::file_size(dir / "trajectory.tum") + fs::file_size(dir / "times.txt") +
                  fs::file_size(dir / "optimized_poses.txt") +
                  fs::file_size(dir / "odom_poses.txt") +
                  fs::file_size(dir / "singlesession_posegraph.g2o"),
              pending);
    writer.AddScanPose(
        StampedPose::FromIsometry(int64_t(200) * 100'000'000, Eigen::Isometry3d::Identity()));
    writer.Flush();
    EXPECT_EQ(inode("trajectory.tum"), trajectory);
    EXPECT_EQ(inode("singlesession_posegraph.g2o"), graph);
    EXPECT_EQ(ReadTum(dir / "trajectory.tum").size(), 201u);
}

TEST(Session, ManifestRoundTripAndBimModel) {
    SessionManifest m = Manifest();
    m.source = "bim";
    m.world_frame = "bim";
    m.model = SessionManifest::Model{"office.ifc", std::string(64, 'a'), {"Level 1", "Level 2"}};
    m.counts = {7, 70};
    m.created = "2026-11-22T10:00:00Z";
    const SessionManifest back = ParseManifest("session.json", SerializeManifest(m));
    EXPECT_EQ(SerializeManifest(back), SerializeManifest(m));
    ASSERT_TRUE(back.model.has_value());
    EXPECT_EQ(back.model->storeys.size(), 2u);
    EXPECT_FALSE(back.host_minus_sensor_ns.has_value());
}

// The recording host's clock offset (map_bim.las's GPS times): kept when known, negative too;
// a session without it stays as it was.
TEST(Session, ManifestKeepsTheClockOffset) {
    SessionManifest m = Manifest();
    EXPECT_EQ(SerializeManifest(m).find("clocks"), std::string::npos);
    for (int64_t ns : {int64_t{1796083200'000'000'000}, int64_t{-42}}) {
        m.host_minus_sensor_ns = ns;
        const SessionManifest back = ParseManifest("session.json", SerializeManifest(m));
        EXPECT_EQ(back.host_minus_sensor_ns, ns);
    }
    std::string text = SerializeManifest(m);
    text.replace(text.find("-42"), 3, "1.5");
    EXPECT_THROW(ParseManifest("session.json", text), FileError);
}

// The indoor cell rule: written, read back; a session written before it (no "rule") was made
// with z_span; an unknown rule is refused naming the field.
TEST(Session, ManifestSaysItsIndoorCellRule) {
    SessionManifest m = Manifest();
    EXPECT_EQ(m.descriptor.cell_rule, "z_stack");
    std::string text = SerializeManifest(m);
    EXPECT_NE(text.find("\"rule\": \"z_stack\""), std::string::npos) << text;
    EXPECT_EQ(ParseManifest("session.json", text).descriptor.cell_rule, "z_stack");
    const size_t at = text.find(",\n      \"rule\"");
    ASSERT_NE(at, std::string::npos) << text;
    std::string older = text;
    older.erase(at, older.find('\n', at + 2) - at);
    EXPECT_EQ(older.find("\"rule\""), std::string::npos) << older;
    EXPECT_EQ(ParseManifest("session.json", older).descriptor.cell_rule, "z_span");
    std::string bad = text;
    bad.replace(bad.find("z_stack"), 7, "z_max");
    try {
        ParseManifest("session.json", bad);
        ADD_FAILURE() << "accepted: " << bad;
    } catch (const FileError& e) {
        EXPECT_NE(std::string(e.what()).find("descriptor.cell_rule.rule"), std::string::npos)
            << e.what();
    }
}

TEST(Session, ManifestErrorsNameTheField) {
    const std::string good = SerializeManifest(Manifest());
    auto expect_field = [](const std::string& text, const std::string& field) {
        try {
            ParseManifest("session.json", text);
            ADD_FAILURE() << "accepted: " << text;
        } catch (const FileError& e) {
            EXPECT_EQ(e.path(), "session.json");
            EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
        }
    };
    auto edit = [&](const std::string& from, const std::string& to) {
        std::string t = good;
        const size_t at = t.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        return t.replace(at, from.size(), to);
    };
    expect_field(edit("\"bimslam-session\"", "\"other\""), "format");
    expect_field(edit("\"version\": 1", "\"version\": 99"), "version");
    expect_field(edit("\"source\": \"rig\"", "\"source\": \"lidar\""), "source");
    expect_field(edit("\"rings\": 4", "\"rings\": \"four\""), "descriptor.rings");
    expect_field(edit("\"rings\": 4", "\"rings\": -4"), "descriptor.rings");
    expect_field(edit("\"max_radius_m\": 10.0,", ""), "descriptor.max_radius_m");
    expect_field(edit("\"keyframes\": 0", "\"keyframes\": 1.5"), "counts.keyframes");
    expect_field("[1, 2]", "JSON object");
    // Broken JSON: the line of the error is named.
    try {
        ParseManifest("session.json", "{\n\"format\": \"bimslam-session\",\n  oops\n}");
        ADD_FAILURE();
    } catch (const FileError& e) {
        EXPECT_EQ(e.line(), 3u) << e.what();
    }
    for (const std::string& bad : {std::string(), std::string("\0\1\2", 3), good.substr(0, 50)}) {
        EXPECT_THROW(ParseManifest("session.json", bad), FileError);
    }
}

TEST(Session, NeverOverwritesSilently) {
    test::TempDir tmp;
    const fs::path dir = tmp / "s";
    WriteSession(dir, 2, true);
    EXPECT_FILE_ERROR(SessionWriter(dir, Manifest()), dir.string(), 0);
    EXPECT_EQ(ReadSession(dir).keyframes.size(), 2u);  // untouched
    // With the flag the old session is replaced.
    WriteSession(dir, 3, true, {.overwrite = true});
    EXPECT_EQ(ReadSession(dir).keyframes.size(), 3u);
    // A folder that is not a session is never deleted, flag or not.
    const fs::path other = tmp / "photos";
    fs::create_directories(other);
    test::WriteBytes(other / "holiday.jpg", "jpeg");
    EXPECT_FILE_ERROR(SessionWriter(other, Manifest(), {.overwrite = true}), other.string(), 0);
    EXPECT_TRUE(fs::exists(other / "holiday.jpg"));
}

TEST(Session, CutOffMidKeyframeReadsBackUpToLastCompleteKeyframe) {
    test::TempDir tmp;
    const fs::path dir = tmp / "s";
    WriteSession(dir, 6, /*finish=*/false);
    // Power lost while keyframe 6 was written: its cloud and descriptor made it, its lines not.
    std::mt19937 rng(1);
    const SessionKeyframe extra = MakeKeyframe(6, rng);
    test::WriteBytes(KeyframeCloudPath(dir, 6), "# .PCD v0.7 - Point Cloud Data file format\nVERS");
    WriteScd(KeyframeDescriptorPath(dir, 6), extra.descriptor);
    // ... and one line file had already been rewritten with 7 lines.
    std::string times = ReadFileToString(dir / "times.txt");
    test::WriteBytes(dir / "times.txt", times + "1800000000.5\n");

    const Session s = ReadSession(dir);
    EXPECT_FALSE(s.complete);
    EXPECT_EQ(s.keyframes.size(), 6u);
    ASSERT_FALSE(s.notes.empty());
    EXPECT_NE(s.notes[0].find("recovered 6"), std::string::npos) << s.notes[0];
    EXPECT_EQ(s.edges.size(), 5u);
    EXPECT_EQ(s.manifest.counts.keyframes, 6u);
    EXPECT_EQ(s.manifest.descriptor.sectors, 6);
    // The same session, when recovery is not allowed, is an error naming session.json.
    EXPECT_FILE_ERROR(ReadSession(dir, {.load_clouds = false, .allow_recovery = false}),
                      (dir / "session.json").string(), 0);
}

TEST(Session, CutOffBeforeFirstFlushRecoversNothing) {
    test::TempDir tmp;
    const fs::path dir = tmp / "s";
    { SessionWriter w(dir, Manifest()); }  // created, nothing written
    const Session s = ReadSession(dir);
    EXPECT_FALSE(s.complete);
    EXPECT_TRUE(s.keyframes.empty());
}

// The line files grow by appends, so a power cut can leave part of a line at the end of any of
// them: recovery drops that part and says so; in a finished session (its files synced before
// session.json) such a line is damage, an error naming the file and line.
TEST(Session, ALineCutOffByAPowerCutIsDroppedOnRecovery) {
    test::TempDir tmp;
    const fs::path dir = tmp / "s";
    WriteSession(dir, 6, /*finish=*/false);
    const auto append = [&](const char* f, const std::string& bytes) {
        test::WriteBytes(dir / f, ReadFileToString(dir / f) + bytes);
    };
    append("times.txt", "1800000000.5");
    append("optimized_poses.txt", "1 0 0 0.5 0 1");
    append("singlesession_posegraph.g2o", "EDGE_SE3:QUAT 4 5 0.1");
    append("trajectory.tum", std::string(7, '\0'));  // a block the disk never got
    const Session s = ReadSession(dir);
    EXPECT_FALSE(s.complete);
    EXPECT_EQ(s.keyframes.size(), 6u);
    EXPECT_EQ(s.edges.size(), 5u);
    EXPECT_EQ(s.trajectory.size(), 18u);
    std::string notes;
    for (const std::string& n : s.notes) notes += n + "\n";
    for (const char* f : {"times.txt: dropped its last 12 bytes",
                          "singlesession_posegraph.g2o: dropped its last 21 bytes",
                          "trajectory.tum: dropped its last 7 bytes"}) {
        EXPECT_NE(notes.find(f), std::string::npos) << f << " in\n" << notes;
    }

    const fs::path done = tmp / "done";
    WriteSession(done, 6, /*finish=*/true);
    test::WriteBytes(done / "times.txt", ReadFileToString(done / "times.txt") + "1800000000.5");
    EXPECT_FILE_ERROR(ReadSession(done), (done / "times.txt").string(), 7);
}

TEST(Session, DamagedFilesAreErrorsNamingFileAndLine) {
    test::TempDir tmp;
    const fs::path good = tmp / "good";
    WriteSession(good, 5, true);
    int case_no = 0;
    // Copies the good session, damages it, and expects an error naming the file and line.
    auto expect = [&](const std::function<void(const fs::path&)>& damage, const std::string& file,
                      size_t line) {
        const fs::path dir = tmp / ("case" + std::to_string(case_no++));
        fs::copy(good, dir, fs::copy_options::recursive);
        damage(dir);
        EXPECT_FILE_ERROR(ReadSession(dir), (dir / file).string(), line);
    };
    expect([](const fs::path& d) { ReplaceInFile(d / "optimized_poses.txt", 4, ""); },
           "optimized_poses.txt", 5);  // count mismatch: the missing 5th line
    expect([](const fs::path& d) { ReplaceInFile(d / "times.txt", 2, "17000x"); }, "times.txt", 3);
    expect(
        [](const fs::path& d) {
            ReplaceInFile(d / "odom_poses.txt", 1, "1 0 0 nan 0 1 0 0 0 0 1 0");
        },
        "odom_poses.txt", 2);
    expect([](const fs::path& d) { ReplaceInFile(d / "SCDs/000003.scd", 1, "1 2 3 4 5"); },
           "SCDs/000003.scd", 2);  // wrong descriptor size
    expect([](const fs::path& d) { ReplaceInFile(d / "SCDs/000002.scd", 3, ""); },
           "SCDs/000002.scd", 3);  // one ring short
    expect([](const fs::path& d) { ReplaceInFile(d / "SCDs/000000.scd", 0, "1 2 3 inf 5 6"); },
           "SCDs/000000.scd", 1);
    expect([](const fs::path& d) { fs::remove(d / "singlesession_posegraph.g2o"); },
           "singlesession_posegraph.g2o", 0);
    expect([](const fs::path& d) { fs::remove(d / "Scans/000004.pcd"); }, "Scans/000004.pcd", 0);
    expect([](const fs::path& d) { fs::copy(d / "SCDs/000000.scd", d / "SCDs/000005.scd"); },
           "SCDs/000005.scd", 0);
    expect([](const fs::path& d) { ReplaceInFile(d / "trajectory.tum", 0, ""); }, "trajectory.tum",
           15);
    expect(
        [](const fs::path& d) {
            ReplaceInFile(d / "singlesession_posegraph.g2o", 6, "EDGE_SE3:QUAT 0 9 0 0 0 0 0 0 1");
        },
        "singlesession_posegraph.g2o", 7);
    expect([](const fs::path& d) { test::WriteBytes(d / "session.json", "{\"format\":"); },
           "session.json", 1);
    EXPECT_FILE_ERROR(ReadSession(tmp / "nothing"), (tmp / "nothing").string(), 0);
}

TEST(Session, GarbageNeverCrashes) {
    test::TempDir tmp;
    const fs::path good = tmp / "good";
    WriteSession(good, 3, true);
    std::vector<fs::path> files;
    for (const auto& e : fs::recursive_directory_iterator(good)) {
        if (e.is_regular_file()) files.push_back(fs::relative(e.path(), good));
    }
    std::mt19937 rng(5);
    for (int i = 0; i < 150; ++i) {
        const fs::path dir = tmp / ("f" + std::to_string(i));
        fs::copy(good, dir, fs::copy_options::recursive);
        const fs::path victim = dir / files[rng() % files.size()];
        const std::string bytes = test::Mutate(ReadFileToString(victim), rng, 256);
        test::WriteBytes(victim, bytes);
        try {
            ReadSession(dir);
        } catch (const FileError& e) {
            EXPECT_NE(std::string(e.what()).find(dir.string()), std::string::npos) << e.what();
        }
        fs::remove_all(dir);
    }
}

TEST(G2o, RejectsUnknownTagsAndBadEdges) {
    EXPECT_FILE_ERROR(ParseG2o("g.g2o", "FIX 0\n"), "g.g2o", 1);
    EXPECT_FILE_ERROR(ParseG2o("g.g2o", "VERTEX_SE3:QUAT 1 0 0 0 0 0 0 1\n"), "g.g2o", 1);
    const std::string v = "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 0 0 0 0 0 0 1\n";
    std::string info;
    for (int r = 0; r < 6; ++r) {
        for (int c = r; c < 6; ++c) info += r == c ? " -1" : " 0";
    }
    EXPECT_FILE_ERROR(ParseG2o("g.g2o", v + "EDGE_SE3:QUAT 0 1 0 0 0 0 0 0 1" + info + "\n"),
                      "g.g2o", 3);
    const G2oGraph g = ParseG2o("g.g2o", v + "# comment\n");
    EXPECT_EQ(g.vertices.size(), 2u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::io
