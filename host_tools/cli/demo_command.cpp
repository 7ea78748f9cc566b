// bimslam demo: the main job end to end on data the project makes itself. It grows with every
// issue; for now: write the sample building as IFC and read it back (IFC++), turn it into its
// BIM reference session (Step 1: grids, walks through every room, simulated scans), simulate a
// Go1 rig's capture of the ground floor (bimslam simulate), run it through the on-board
// firmware (bimslam-rig replay, a separate process, LCM recorded by lcm-logger) into a session,
// score it against the ground truth (bimslam evaluate), read the session back, and anchor it
// into BIM coordinates (Step 2, bimslam anchor), scored with no alignment.
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
#include "host_tools/anchor/anchor_output.hpp"
#include "host_tools/anchor/anchoring.hpp"
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

    // 7. Step 2: the session anchored into BIM coordinates with no initial pose (bimslam
    //    anchor: Scan Context candidates verified by registration, consistency, pose graph), and
    //    scored against the ground truth, which is in BIM coordinates: no alignment.
    const fs::path anchor_dir = out / "anchor";
    const anchor::AnchorConfig anchor_config;
    anchor::LoadOptions load;
    std::vector<anchor::AnchorSession> sessions;
    sessions.push_back(anchor::LoadAnchorSession(reference_dir, load));
    sessions.push_back(anchor::LoadAnchorSession(session_dir, load));
    const anchor::AnchorResult anchored = anchor::Anchor(sessions, anchor_config);
    anchor::WriteAnchorOutput(anchor_dir, sessions, anchored, anchor_config, opt.overwrite);
    const anchor::SessionResult& a = anchored.sessions.front();
    const bool anchored_ok = a.verdict == anchor::Verdict::kAnchored;
    std::cout << "  anchoring " << anchor::ToString(a.verdict) << ": " << a.reason << "; in "
              << std::setprecision(1) << anchored.times.total_s << " s\n";
    if (anchored_ok) {
        evaluation::EvaluationConfig none;
        none.align = evaluation::Alignment::kNone;
        const evaluation::EvaluationResult ab = evaluation::EvaluateFiles(
            anchor_dir / "session" / "trajectory_bim.tum", capture_dir / "ground_truth.tum", none);
        std::cout << "  accuracy in BIM coordinates APE " << std::setprecision(2)
                  << ab.ape_trans_m.rmse * 100 << " cm (max " << ab.ape_trans_m.max * 100 << ") / "
                  << ab.ape_rot_deg.rmse << " deg with no alignment (the paper's "
                  << "BIM-SLAM: 10.6 cm / 2.07 deg)\n"
                  << std::setprecision(1) << "           " << anchor_dir.string()
                  << "/: anchor.json, loops.json, posegraph.g2o, session/ (world frame bim)\n";
    }
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
        << "  anchor/       the session in BIM coordinates, the loops and the verdict "
           "(bimslam anchor --reference "
        << reference_dir.string() << " --query " << session_dir.string() << " -o "
        << anchor_dir.string() << ")\n"
        << "demo " << (read_ok && anchored_ok ? "finished" : "FAILED") << " in " << Seconds(t_start)
        << " s\n";
    return read_ok && anchored_ok ? kExitOk : kExitFailure;
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
