// bimslam demo: the main job end to end on data the project makes itself. It grows with every
// issue; for now: write the sample building as IFC and read it back (IFC++), turn it into its
// BIM reference session (Step 1: grids, walks through every room, simulated scans), simulate a
// Go1 rig's capture of the ground floor (bimslam simulate), run it through the on-board
// firmware (bimslam-rig replay, a separate process, LCM recorded by lcm-logger) into a session,
// score it against the ground truth (bimslam evaluate), read the session back, and recognise the
// rig's places among the reference's keyframes.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/io/sha256.hpp"
#include "algorithms/keyframes/keyframe_selector.hpp"
#include "algorithms/scancontext/candidate_index.hpp"
#include "algorithms/scancontext/descriptor.hpp"
#include "host_tools/bim/coverage_path.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/reference_session.hpp"
#include "host_tools/bim/sample_building.hpp"
#include "host_tools/cli/command.hpp"
#include "host_tools/cli/rig_replay.hpp"
#include "host_tools/evaluation/trajectory_metrics.hpp"
#include "host_tools/simulate/scenario.hpp"
#include "host_tools/simulate/simulate.hpp"

namespace bimslam::cli {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct DemoOptions {
    std::string out = "demo_output";
    bool overwrite = false;
    int columns = 1024;
    double duration_s = 120;
};

double Seconds(Clock::time_point since) {
    return std::chrono::duration<double>(Clock::now() - since).count();
}

double Yaw(const Eigen::Isometry3d& T) { return std::atan2(T.linear()(1, 0), T.linear()(0, 0)); }

std::string FixedString(double v) {
    std::ostringstream s;
    s << std::fixed << std::setprecision(1) << v;
    return s.str();
}

double WrapAngle(double a) { return std::remainder(a, 2.0 * M_PI); }

int RunDemo(const DemoOptions& opt) {
    const auto t_start = Clock::now();
    const fs::path out = opt.out;
    const fs::path building_file = out / "building.ifc";
    const fs::path reference_dir = out / "reference";
    const fs::path plan_dir = out / "plan";
    const fs::path session_dir = out / "session";
    const fs::path capture_dir = out / "capture";
    for (const fs::path& p : {building_file, reference_dir, session_dir, capture_dir}) {
        if (fs::exists(p) && !opt.overwrite) {
            throw common::FileError(
                common::StatusCode::kAlreadyExists, out.string(), 0,
                "holds an earlier demo; pass --overwrite or choose another --out");
        }
    }
    fs::remove_all(capture_dir);
    fs::create_directories(capture_dir);
    std::cout << std::fixed << std::setprecision(1);

    // 1. The building: the project's sample office as IFC4, read back through IFC++.
    const auto t_building = Clock::now();
    bim::WriteSampleBuilding(building_file);
    const bim::BimModel model = bim::LoadIfc(building_file);
    std::cout << "bimslam demo: the sample office building, " << model.storeys.size()
              << " storeys, " << model.elements.size() << " elements, "
              << model.mesh.triangles.size() << " triangles (IFC4 written and read back through "
              << "IFC++ in " << std::setprecision(2) << Seconds(t_building) << " s)\n"
              << std::setprecision(1) << "           " << building_file.string() << "\n";

    // 2. Step 1: its reference session, scans simulated along a walk through every room.
    bim::ReferenceSessionOptions ro;
    ro.plan_dir = plan_dir;
    ro.overwrite = opt.overwrite;
    ro.lidar = simulation::LidarModel::DefaultOs1_32(opt.columns);
    const auto t_reference = Clock::now();
    const bim::ReferenceSessionReport ref =
        bim::WriteReferenceSession(model, io::Sha256File(building_file), reference_dir, ro);
    const double reference_s = Seconds(t_reference);
    int rooms = 0;
    double walk_m = 0;
    for (const auto& st : ref.storeys) {
        rooms += st.rooms;
        walk_m += st.walk_m;
    }
    std::cout << "  reference " << ref.keyframes << " keyframes along " << walk_m
              << " m of walk through " << rooms << " rooms, the structure ray-cast in "
              << reference_s << " s (" << std::setprecision(0) << ref.walk_s / reference_s
              << "x real time at 0.5 m/s)\n"
              << std::setprecision(1) << "           " << reference_dir.string()
              << ", grids and walks in " << plan_dir.string() << "\n";

    // 3. The rig's capture: a Go1 trotting the ground floor's coverage walk, simulated as the rig
    //    records it (host_tools/simulate): Ouster lidar + IMU packets in a pcap, the Go1's CAN
    //    log, and the ground truth; in the real building, furniture and doors included, which the
    //    reference leaves out.
    simulate::Scenario scenario = simulate::DefaultScenario(simulate::Platform::kGo1);
    scenario.model = building_file;
    scenario.duration_s = opt.duration_s;
    scenario.sensor.lidar_mode = std::to_string(opt.columns) + "x10";
    scenario.seed = 7;
    const simulate::CaptureReport cap =
        simulate::SimulateCapture(scenario, model, io::Sha256File(building_file), capture_dir);
    std::cout << "  captured " << cap.frames << " frames, " << cap.duration_s << " s of a Go1 "
              << "trotting the ground floor's " << cap.walk_length_m << " m walk (OS-1-32 "
              << scenario.sensor.lidar_mode << " " << scenario.sensor.udp_profile << ", "
              << cap.imu_packets << " IMU packets, " << cap.can_frames << " Go1 CAN frames), "
              << "simulated in " << cap.wall_s << " s\n           " << capture_dir.string()
              << "/: lidar.pcap, metadata.json, go1_can.log, ground_truth.tum\n";

    // 4. The on-board LiDAR odometry and keyframe selection, run offline on the capture exactly
    //    as bimslam-rig runs them (bimslam odometry).
    const RigReplayRun odo = RunRigReplay(capture_dir, out / "rig");
    fs::remove_all(session_dir);
    fs::rename(odo.session, session_dir);
    std::cout << "  bimslam-rig replay " << odo.scans << " scans, " << odo.keyframes
              << " keyframes (1 m / 10 deg, indoor Scan Context each) in " << odo.wall_s
              << " s, as fast as the machine goes (lossless; the latency includes queueing then: "
                 "last packet to odometry on LCM p50 "
              << std::setprecision(2) << odo.latency_p50_ms << " ms, max " << odo.latency_max_ms
              << std::setprecision(1) << " ms)\n           " << session_dir.string()
              << "/ (trajectory.tum: every scan)"
              << (odo.lcm_log.empty() ? "" : ", LCM recorded in " + odo.lcm_log.string()) << "\n";
    const keyframes::KeyframeConfig keyframe_config;

    // 5. Its accuracy against the simulator's ground truth (bimslam evaluate).
    const evaluation::EvaluationResult ev = evaluation::EvaluateFiles(
        session_dir / "trajectory.tum", capture_dir / "ground_truth.tum", {});
    std::cout << "  accuracy APE " << std::setprecision(2) << ev.ape_trans_m.rmse * 100 << " cm / "
              << ev.ape_rot_deg.rmse << " deg RMSE after SE(3) alignment, drift "
              << ev.drift_percent << " % over " << std::setprecision(1) << ev.distance_m
              << " m, no loop closure (the paper's SC-A-LOAM: 12.4 cm / 2.3 deg)\n";

    // 6. Read the session back: complete, every keyframe and every scan pose there.
    const auto t_read = Clock::now();
    const io::Session s = io::ReadSession(session_dir);
    const bool read_ok = s.complete && s.keyframes.size() == odo.keyframes &&
                         s.trajectory.size() == odo.scans &&
                         s.edges.size() + 1 == s.keyframes.size();
    std::cout << "  read     " << s.keyframes.size() << " keyframes, " << s.edges.size()
              << " odometry edges, " << s.trajectory.size() << " scan poses back in "
              << Seconds(t_read) << " s: " << (read_ok ? "complete" : "INCONSISTENT") << "\n";

    // 7. Place recognition across sessions, the start of Step 2: each rig keyframe against all
    //    keyframes of the BIM reference (both storeys) by Scan Context. The rig's keyframes are
    //    in its odometry frame; until anchoring exists they are put in the BIM frame with the
    //    simulator's ground-truth pose of the first scan, only to score the matches.
    const std::vector<io::StampedPose> truth = io::ReadTum(capture_dir / "ground_truth.tum");
    const Eigen::Isometry3d T_bim_odom =
        truth.empty() ? Eigen::Isometry3d::Identity() : truth.front().Pose();
    const io::Session reference = io::ReadSession(reference_dir, {.load_clouds = false});
    scancontext::CandidateIndex index(keyframe_config.descriptor);
    for (const auto& kf : reference.keyframes) {
        if (!index.Add(kf.descriptor).ok()) return kExitFailure;
    }
    index.Build();
    int found = 0;
    double yaw_err_sum = 0.0;
    for (const auto& kf : s.keyframes) {
        const auto match = index.Query(kf.descriptor);
        if (!match) continue;
        const auto& T_ref = reference.keyframes[match->index].T_world_lidar;
        const Eigen::Isometry3d T_bim_lidar = T_bim_odom * kf.T_world_lidar;
        if ((T_ref.translation() - T_bim_lidar.translation()).norm() > 2.0) continue;
        ++found;
        yaw_err_sum += std::abs(WrapAngle(match->yaw - (Yaw(T_bim_lidar) - Yaw(T_ref))));
    }
    std::cout << "  matched  " << found << "/" << s.keyframes.size()
              << " rig keyframes to a BIM reference keyframe within 2 m by Scan Context"
              << (found
                      ? ", mean yaw error " + FixedString(yaw_err_sum / found * 180 / M_PI) + " deg"
                      : "")
              << "\n";
    std::cout
        << "results in " << out.string() << "/:\n"
        << "  building.ifc  the sample building (bimslam bim info " << building_file.string()
        << ")\n"
        << "  reference/    its BIM reference session; plan/ its grids and walks (PGM, PNG, TUM)\n"
        << "  capture/      the rig's capture (bimslam ouster info " << capture_dir.string()
        << "/lidar.pcap; capture.json lists its files)\n"
        << "  session/      the rig's session: keyframes, poses, descriptors, trajectory "
           "(bimslam session info "
        << session_dir.string() << "; bimslam evaluate --est " << session_dir.string()
        << "/trajectory.tum --ref " << capture_dir.string() << "/ground_truth.tum)\n"
        << "demo " << (read_ok ? "finished" : "FAILED") << " in " << Seconds(t_start) << " s\n";
    return read_ok ? kExitOk : kExitFailure;
}

}  // namespace

void AddDemoCommand(CLI::App& app, int& exit_code) {
    auto opt = std::make_shared<DemoOptions>();
    CLI::App* demo = app.add_subcommand(
        "demo",
        "Run the main job end to end on a building and a walk the project generates "
        "itself, and print what it did and where the results are.");
    demo->add_option("--out,-o", opt->out, "output folder")->capture_default_str();
    demo->add_flag("--overwrite", opt->overwrite, "replace the results of an earlier demo");
    demo->add_option("--columns", opt->columns, "columns per scan (512, 1024 or 2048)")
        ->check(CLI::IsMember({512, 1024, 2048}))
        ->capture_default_str();
    demo->add_option("--duration", opt->duration_s,
                     "seconds of the rig's walk of the ground floor (0: the whole walk once)")
        ->check(CLI::Range(0.0, 3600.0))
        ->capture_default_str();
    demo->callback([opt, &exit_code] { exit_code = Run([&] { return RunDemo(*opt); }); });
}

}  // namespace bimslam::cli
