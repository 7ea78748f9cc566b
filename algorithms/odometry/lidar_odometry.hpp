// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// LiDAR odometry: one scan in, its pose in the odometry frame out, in bounded time. No thread and
// no I/O of its own: the rig's odometry module and `bimslam odometry` run this same code.
//
// Per scan (README.md, "Per scan"):
// 1. Prediction of the motion since the previous scan: constant velocity by default; the Go1's
//    body motion (MotionPrior, moved into the lidar frame by T_base_lidar) replaces it when
//    present; the Ouster IMU's integrated gyro replaces its rotation when present.
// 2. Preprocessing: range crop, self-filter, deskew with that motion (the gyro's rotation inside
//    the scan when present), voxel downsampling at sizes adapted to the point count
//    (Preprocessor).
// 3. Registration of the downsampled scan to the local map from the prediction (ScanRegistration,
//    a Gauss-Newton step per association): the pose at the scan start and a correction of the
//    motion during the sweep, with degenerate directions kept at the prediction, and
//    correspondences within a distance adapted to how far the predictions have been off
//    (KISS-ICP's adaptive threshold).
//    Without the correction (its default), when the motion the estimate implies differs from
//    the one the scan was deskewed with, the scan is deskewed again with it and registered once
//    more. A start in motion: the first scan was deskewed with no motion; at the second scan, once
//    the velocity is known, the first scan is deskewed again with it, the map rebuilt from it, and
//    the second scan registered again (start_refinements, once; not when that registration
//    was degenerate). A registration that turns the scan against the gyro by more than
//    imu_rotation_gate sigmas is done again with the gyro's rotation held, translation only.
// 4. The map gets the scan's fine points, corrected, at the estimated pose and forgets what lies
//    beyond the scene's extent.
//
// Time. The whole call is budgeted (budget_ms): registration stops at its share of the budget
// with its best estimate, a step that would not fit is not begun, and every step cut either way
// sets kOverBudget and its BudgetStep bit (OdometryResult::budget_cut). A registration the
// deadline stopped before its first iteration has no evidence: a later step's leaves the one
// before it in place, the first's leaves the prediction (kRegistrationFailed). Frames: `lidar` is
// the Ouster sensor frame of the points and of the IMU; `odom` is the lidar frame of the first
// scan. Time stamps: one clock for scans, IMU and body motion (the sensor's; the caller converts
// the Go1's).
//
// Allocation: none per scan after the first (tests/unit/odometry/allocation_test.cpp).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <chrono>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/common/point_cloud.hpp"
#include "algorithms/common/se3.hpp"
#include "algorithms/odometry/edge_features.hpp"
#include "algorithms/odometry/gravity_tilt.hpp"
#include "algorithms/odometry/imu_height.hpp"
#include "algorithms/odometry/motion_prior.hpp"
#include "algorithms/odometry/preprocess.hpp"
#include "algorithms/odometry/registration_check.hpp"
#include "algorithms/odometry/scan_registration.hpp"
#include "algorithms/odometry/voxel_map.hpp"

namespace bimslam::odometry {

// An IMU sample in the lidar frame and the scans' clock.
struct ImuMeasurement {
    int64_t t_ns = 0;
    Eigen::Vector3d gyro = Eigen::Vector3d::Zero();   // rad/s
    Eigen::Vector3d accel = Eigen::Vector3d::Zero();  // m/s^2
};

// The edge map of LOAM's edge features: lines in 0.6 m voxels.
inline VoxelMapConfig EdgeMapConfig() {
    VoxelMapConfig c;
    c.fit_lines = true;
    c.min_plane_points = 4;
    c.min_point_spacing = 0.04;
    c.max_plane_thickness = 0.05;
    c.max_voxels = 10000;
    return c;
}

struct LidarOdometryConfig {
    PreprocessConfig preprocess;
    VoxelMapConfig map;
    RegistrationConfig registration;
    // Every registration judged by its own evidence (registration_check.hpp): kCheckFailed.
    RegistrationCheckConfig check;
    // LOAM edge features (edge_features.hpp) registered point-to-line to an edge map, on top of
    // the point-to-plane registration. Off: measured on the project's captures, they took
    // 1.25-1.6x the time for 4 % less error, and failed once without the IMU (README.md).
    bool edge_features = false;
    EdgeFeatureConfig edges;
    VoxelMapConfig edge_map = EdgeMapConfig();
    MotionPriorConfig body_prior;
    double budget_ms = 50.0;         // per scan, 10 Hz
    double map_update_share = 0.15;  // of the budget kept for the map update
    // The lidar on the Go1's body (for the body-motion prior): 5 cm ahead, 28 cm above.
    Eigen::Isometry3d T_base_lidar = Eigen::Isometry3d(Eigen::Translation3d(0.05, 0.0, 0.28));
    bool use_imu = true;
    bool use_body_motion = true;
    size_t imu_capacity = 2048;   // samples (20 s at the Ouster's 100 Hz)
    double max_imu_gap_s = 0.05;  // longer gaps: the gyro does not cover the interval
    // Standard deviation of the constant-velocity prediction per scan [m m m rad rad rad]: the
    // fallback along degenerate directions when there is no body motion.
    common::Vector6d constant_velocity_sigma =
        (common::Vector6d() << 0.05, 0.05, 0.05, 0.02, 0.02, 0.02).finished();
    double imu_rotation_sigma = 0.003;  // rad per scan, the gyro's rotation
    // With the IMU, after a scan that did not see the height: the height predicted from the
    // accelerometers (imu_height.hpp) instead of the constant velocity's or the legs' (planar),
    // once that filter knows its vertical velocity, and kept there unless the scan sees it
    // (kImuHeight). Scans after one that saw the height are predicted and registered as before.
    bool imu_height = true;
    ImuHeightConfig imu_height_filter;
    // With the IMU, once the accelerometers' filter knows its vertical velocity: the motion
    // during a sweep along gravity is the filter's, carried through the sweep by the
    // accelerometers, not the constant velocity's (README.md, "The bob within a sweep"). A
    // person's steps move the sensor 2-4 cm up and down twice a second, about 0.25 m/s at most:
    // half a sweep of it is a centimetre, which the constant velocity over 0.4 s averages away.
    // With the legs' prior (use_body_motion) too since stop 79: with deskew rounds from 1 cm the
    // Go1's feet's impacts in the accelerometers no longer made its stair walks worse, its body
    // rising a step at a time on a flight (README.md, "Deskew rounds from 1 cm").
    bool imu_vertical_deskew = true;
    // Nor after a scan whose surfaces facing up or down carried under this share of its
    // registration's weights (RegistrationResult::axis_share): the filter's velocity has no floor
    // or ceiling behind it then. The hand-held walks' scans carry 0.07-0.20 at their 5th
    // percentile (median 0.28-0.31); a bare shaft's edge voxels 0.014, and deskewed there from
    // the filter a climb at 1.6 m/s ended 52 cm off (LidarOdometry.AStopInAShaft...).
    double vertical_deskew_share = 0.05;
    // With the IMU and imu_height: each registered pose levelled by gravity, the accelerometers'
    // filter of the frame's tilt and their bias (gravity_tilt.hpp; README.md, "Gravity holds the
    // tilt"), before the map takes the scan.
    bool imu_tilt = true;
    GravityTiltConfig imu_tilt_filter;
    // A scan saw the height when the surfaces facing up or down it hit carry at least this share
    // of its registration's weights (RegistrationResult::axis_share), as vertical_deskew_share
    // (above: a hand-held walk's scans 0.07-0.20 at their 5th percentile, a bare shaft's edge
    // voxels 0.014). 0.01 until the registration's finer kernel (scan_registration.hpp): with
    // it a shaft's edge voxels reached 0.015-0.024 on some scans and their height, counted as
    // seen, took the climb 1.1 m off (LidarOdometry.AStopInAShaft...).
    double height_seen_share = 0.05;
    // A height seen again while the accelerometers' filter is more uncertain than this (1-sigma,
    // m) is ambiguous (kHeightAmbiguous): half of the lowest riser of a stair (15 cm; most rise
    // 15-20 cm), beyond which the registration can settle on the step next to the true one. Said,
    // not acted on: the estimate is the same with it.
    double height_ambiguous_sigma = 0.075;
    // At rest over the gravity window: the specific force's spread (m/s^2, the root of its
    // per-axis variances' sum) and the gyro's largest rate (rad/s) under these.
    double rest_accel_sigma = 0.1;
    double rest_gyro = 0.05;
    double gravity_window_s = 1.0;  // the accelerometers' mean over this long: gravity's direction
    // Scans the constant velocity is averaged over. One scan's motion is noisy, and a velocity
    // that is wrong deskews the next scan wrongly, whose pose is then wrong the other way: with
    // one scan this can ring (measured on hand-held captures); averaging over a few damps it.
    int velocity_window = 4;
    // A scan is deskewed again with its estimated motion when that differs from the predicted
    // one by more than this over the sweep (metres of translation + 10 m x radians of rotation:
    // the displacement of a point 10 m away). Not with the sweep's motion correction, which
    // estimates that motion itself.
    double redeskew_threshold = 0.02;
    // The same for a scan deskewed with the gyro whose registration was not degenerate. With the
    // gyro most scans' predictions were within 2 cm and left as they were, and a sweep deskewed
    // with a translation off by e fits best about its middle (README.md, "Deskew rounds from 1
    // cm"): the office's flat minutes 0.53-0.58 -> 0.37-0.42 cm, the stair walks of seeds 3-4
    // (not those it was chosen on) better or the same. Not without the gyro: there the rounds
    // are under-relaxed steps (deskew_step) and ending them at 1 cm took the office's LiDAR-only
    // Go1 descent 2.30 -> 12.66 cm. Not after a degenerate registration: along its weak direction
    // the estimate is the prediction's, and a round there follows what little the map holds (the
    // map's edge voxels in a bare shaft: LidarOdometry.AStopInAShaft... 27.7 cm off at 1 cm).
    double gyro_redeskew_threshold = 0.01;
    // With the gyro, a round whose motion moves the points by at most this much over the sweep
    // (the same measure) moves the points the voxel filters chose (Preprocessor::Redeskew, about
    // a fifth of the cost); a larger move, or any round without the gyro, preprocesses the scan
    // again, filters included. Half the finest map voxel: the filters' choice still holds but for
    // points near a border. Without the gyro the rounds move the points by 10-40 cm, and moving
    // the chosen points measured worse there even under this limit (README.md, "A deskew round
    // moves the chosen points").
    double max_redeskew_move = 0.05;
    // Rounds of deskewing again and registering, while the motion still moves by more than the
    // threshold: a fixed-point iteration of deskew and pose. Without the IMU one round left a
    // sudden turn's scan (6 deg/scan from 1) most of the way at the prediction; three took the
    // LiDAR-only minutes from 1.7-4.4 to 1.2-2.7 cm (README.md, "Deskew until it holds"). Rounds
    // after the first are not made when the registration was degenerate: along a weak direction
    // the motion is the prediction's, and iterating on it moved Office_A's Go1 walk 4 -> 14 cm.
    int max_deskew_rounds = 3;
    // Without the gyro, a round deskews with a motion moved this share of the way from the one
    // the scan was deskewed with to the estimated one (an under-relaxed fixed-point step). A scan
    // deskewed with a motion that is off by e over the sweep fits best at the sweep's middle, so
    // the pose at its start, and the motion estimated from it, come out off by about -e/2: full
    // steps (1) halve the difference and flip its sign each round (median 35, 18, 9 cm over three
    // rounds on a Go1 minute, so redeskew_threshold never ended them), and a step of 2/3 lands on
    // the fixed point of e -> -e/2 at once (README.md, "Deskew rounds that converge"). With the
    // gyro the sweep's rotation is measured, not iterated, and the step is a full one.
    double deskew_step = 2.0 / 3.0;
    // The prior of the sweep's motion correction (scan_registration.hpp) [m m m rad rad rad] over
    // one sweep: how far the predicted motion during a scan may be off. Without the IMU the trot's
    // wobble puts the rotation up to 2 deg off; with it, the gyro's rotation is good to a few
    // hundredths of a degree (imu_correction_sigma). Zero turns the correction off.
    common::Vector6d correction_sigma = common::Vector6d::Zero();
    double imu_correction_sigma = 0.002;  // rad over a sweep, with the gyro
    // A registration whose rotation differs from the gyro's by more than this many
    // imu_rotation_sigma is done again from the prediction with the gyro's rotation held, for the
    // translation only (kContradictsGyro): over one scan the gyro is good to a few hundredths of
    // a degree, and a scan that turns by more followed something that moved (a door leaf in
    // view). 0: off.
    double imu_rotation_gate = 3.0;
    // With the Go1's legs and the IMU: when the legs' translation over the interval to this scan
    // differs from the LiDAR's own constant velocity's by more than this (m/s), and the previous
    // scan was well constrained, the scan is deskewed and registered from the constant
    // velocity's translation instead (kContradictsLegs). Not without the IMU, where the
    // constant velocity misses the trot's wobble (measured: it fired 8-15 times a minute there
    // and raised the worst error from 9-11 to 13-15 cm). A foot that slips reads a fraction of the
    // true speed for a few tenths of a second; deskewed and started from it, the registration kept
    // part of the slip (README.md, "Foot slips"). Not after a degenerate scan: along a
    // corridor's axis the constant velocity is not measured, the legs are. 0: off.
    double body_translation_gate = 0.25;
    // kMotionCorrected when the correction moves a point 10 m away by more than this at the end
    // of the sweep (m).
    double correction_flag_m = 0.02;
    // Correspondences: within 3 sigma of how far the predictions have been off (KISS-ICP, Vizzo
    // et al., RA-L 2023): sigma^2 is the mean over recent scans (exponential, model_error_scans)
    // of (|translation error| + extent * rotation error)^2 of the prediction against the
    // estimate, extent being the scene's (the 90th percentile of the range, at most 60 m). Clamped
    // to [min, max]; initial_correspondence_distance until a few scans have been seen.
    double min_correspondence_distance = 0.5;  // m
    double max_correspondence_distance = 2.0;  // m
    double initial_correspondence_distance = 1.0;
    double model_error_scans = 50;
    // A start in motion (header, step 3): times the first scan is deskewed again and the second
    // registered again; 0 turns it off. Once: a handheld capture starting at 1.5 m/s had its
    // first scan-to-scan motion 4.5 cm for 14.5 cm true without it (the 0.13 for 0.245 m)
    // and 14.8 cm with it; APE 1.95 -> 0.97 cm over its 10 s (README "Start in motion").
    int start_refinements = 1;
    // The map's radius follows the scene's extent: map_extent_factor x the scans' 90th range
    // percentile, within [min_map_radius, map.max_distance].
    double map_extent_factor = 1.5;
    double min_map_radius = 35.0;  // m
    // The self-filter box in the platform's base frame (T_base_lidar moves it into the lidar
    // frame: a rotated mount keeps it where the body is), used when self_box_in_base. The default
    // is the Go1's trunk and legs (0.65 x 0.28 m trunk, standing 0.32 m above the floor).
    bool self_box_in_base = true;
    Eigen::Vector3d self_box_base_min = {-0.40, -0.25, -0.37};
    Eigen::Vector3d self_box_base_max = {0.40, 0.25, 0.18};

    void Validate() const;
};

enum OdometryFlag : uint32_t {
    kFirstScan = 1u << 0,
    kOverBudget = 1u << 1,          // the budget cut a step (OdometryResult::budget_cut)
    kDegenerate = 1u << 2,          // some directions came from the prediction
    kRegistrationFailed = 1u << 3,  // too few correspondences, or none in time: the prediction
    kNotConverged = 1u << 4,
    kBodyPriorUsed = 1u << 5,
    kImuUsed = 1u << 6,
    kTooFewPoints = 1u << 7,      // the scan kept fewer points than registration needs
    kDeskewedAgain = 1u << 8,     // deskewed and registered a second time (step 3)
    kStartRefined = 1u << 9,      // the second scan: the first deskewed again (a start in motion)
    kMotionCorrected = 1u << 10,  // the sweep's motion correction exceeded correction_flag_m
    kContradictsGyro = 1u << 11,  // the scan turned against the gyro: the gyro's rotation held
    kContradictsLegs = 1u << 12,  // the legs' translation disagreed: the LiDAR's velocity used
    kCheckFailed = 1u << 13,    // the registration failed its own evidence (registration_check.hpp)
    kHeadingsTried = 1u << 14,  // registered again from other headings (a weak prediction)
    // The registration judged was stopped by the deadline (kOverBudget): a check it fails is of
    // an unfinished registration (TrajectoryTrust bridges it where the gyro or legs predicted).
    kCutShort = 1u << 15,
    kImuHeight = 1u << 16,  // the predicted height came from the accelerometers
    // With the IMU: the scan did not see the height (height_seen_share), so its height is a
    // prediction's (TrajectoryTrust counts how long in a row).
    kHeightUnseen = 1u << 17,
    // With the IMU: the scan saw the height again while the accelerometers' height was more
    // uncertain than height_ambiguous_sigma, so the registration's height is the nearest stair
    // tread's (or floor's) to the guess: it may be off by whole risers (TrajectoryTrust says
    // where). Office_A's Go1 climb: sigma 30 cm, then 1 m low for the rest of the walk.
    kHeightAmbiguous = 1u << 18,
};

// The steps of a scan the budget cut (OdometryResult::budget_cut): a registration stopped at the
// deadline, or a step not begun because the deadline had passed or it would not fit before it.
enum BudgetStep : uint32_t {
    kCutRegistration = 1u << 0,     // the registration from the prediction
    kCutGyroGate = 1u << 1,         // the registration again with the gyro's rotation held
    kCutHeadings = 1u << 2,         // other headings (a registration, or the ones not tried)
    kCutStartRefinement = 1u << 3,  // a start in motion's second registration
    kCutDeskewRound = 1u << 4,      // a round of deskewing again (its registration, or not begun)
};

// "registration, deskew round" for the BudgetStep bits set; "" for none.
std::string BudgetCutText(uint32_t steps);

// Why step 3's rounds of deskewing again ended (OdometryResult::deskew_stop).
enum class DeskewStop : uint8_t {
    kNotTried,    // not this scan (the first, no time per point, deskew off, a start refined)
    kHolds,       // the estimated motion agrees with the one the scan was deskewed with
    kDeadline,    // another round needed would not fit before the deadline, or was stopped first
    kDegenerate,  // the last registration was degenerate: its velocity is the prediction's
    kRoundsDone,  // max_deskew_rounds made
    kFailed,      // a round's registration failed
};

struct OdometryResult {
    int64_t stamp_ns = 0;  // the scan's start
    Eigen::Isometry3d T_odom_lidar = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_prev_lidar = Eigen::Isometry3d::Identity();  // motion since the last scan
    // Covariance of that motion, [rho; phi] as a right perturbation (lidar frame).
    common::Matrix6d covariance = common::Matrix6d::Identity() * 1e-4;
    uint32_t flags = 0;
    uint32_t check_reasons = 0;  // with kCheckFailed: CheckReason bits
    uint32_t budget_cut = 0;     // with kOverBudget: the BudgetStep bits of the steps cut
    PreprocessStats preprocess;
    RegistrationResult registration;
    size_t map_voxels = 0;
    size_t map_points = 0;
    size_t edge_points = 0;  // with edge_features: LOAM edge points of this scan
    int deskew_rounds = 0;   // times this scan was deskewed and registered again (step 3)
    DeskewStop deskew_stop = DeskewStop::kNotTried;
    double correspondence_distance = 0;  // m, the adaptive threshold this scan used
    // With the IMU's height filter (imu_height.hpp): its height's 1-sigma after this scan, m;
    // NaN without it. Where the scans do not see the height it grows with the accelerometers'
    // noise and bias over the time unseen.
    double height_sigma = std::numeric_limits<double>::quiet_NaN();
    double map_radius = 0;  // m, the map kept around the sensor
    // Wall time of the steps: preprocess_ms the scan's first preprocessing only; register_ms
    // everything from there to the map update, so the deskew rounds and the start's refinement
    // (their preprocessing again included) count there; map_ms the map update.
    double preprocess_ms = 0, register_ms = 0, map_ms = 0, total_ms = 0;
};

class LidarOdometry {
public:
    using Clock = std::chrono::steady_clock;

    explicit LidarOdometry(const LidarOdometryConfig& config = {});

    // Inputs between scans, in time order. Out of order or non-finite samples are dropped and
    // counted (the hot path never throws).
    void AddImu(const ImuMeasurement& imu);
    void AddBodyMotion(const BodyMotionSample& sample);

    // One scan (lidar frame, time offsets from scan.stamp): its pose. Scans must come in time
    // order; a scan not after the previous one is ignored (kTooFewPoints, pose unchanged).
    const OdometryResult& Process(const common::PointCloud& scan);

    // The last scan's kept points, deskewed into its lidar frame at its start (the keyframe
    // cloud), valid until the next Process().
    const common::PointCloud& deskewed() const { return preprocessor_.deskewed(); }
    const VoxelMap& map() const { return map_; }
    const LidarOdometryConfig& config() const { return config_; }
    uint64_t dropped_inputs() const { return dropped_inputs_; }
    size_t scans() const { return scans_; }

private:
    // Rotation of the lidar at t1 in the lidar at t0 from the gyro; false when the buffer does
    // not cover [t0, t1].
    bool IntegrateGyro(int64_t t0_ns, int64_t t1_ns, Eigen::Quaterniond* q) const;
    // Calls piece(sample, dt_s) for each IMU sample's share of [t0, t1] in time order (each held
    // until the next); false, having called nothing, when the buffer does not cover [t0, t1] or
    // has a gap longer than max_imu_gap_s in it.
    template <typename Piece>
    bool ForImuPieces(int64_t t0_ns, int64_t t1_ns, Piece&& piece) const;
    // The accelerometers' height filter (imu_height): started at the first scan with the IMU
    // (gravity's direction from the accelerometers' mean), moved on to t1 from the lidar's
    // rotation R0 at t0 and the gyro (false, and the filter stopped to start again, when the IMU
    // does not cover the interval), and told what each scan saw of the height.
    void StartImuHeight();
    bool PropagateImuHeight(int64_t t0_ns, int64_t t1_ns, const Eigen::Matrix3d& R0);
    // Calls sample(R, imu, dt_s) for each IMU sample's share of [t0_ns, t1_ns] (ForImuPieces), R
    // the lidar's rotation halfway through it: R0 * *q at t0_ns, *q carried to t1_ns by the gyro.
    // False when the IMU does not cover the span.
    template <typename Sample>
    bool ForImuRotations(int64_t t0_ns, int64_t t1_ns, const Eigen::Matrix3d& R0,
                         Eigen::Quaterniond* q, Sample&& sample) const;
    // Moves the filter *f over [t0_ns, t1_ns] by the accelerometers (ForImuRotations); false when
    // the IMU does not cover the span.
    bool PropagateHeight(ImuHeight* f, int64_t t0_ns, int64_t t1_ns, const Eigen::Matrix3d& R0,
                         Eigen::Quaterniond* q) const;
    void PredictHeight();
    // The motion during a scan: constant velocity `twist`, the gyro's rotation when it covers it.
    // *used_gyro (optional): whether the gyro covered it.
    ScanMotion MotionFor(const common::Vector6d& twist, double duration, int64_t stamp,
                         bool* used_gyro = nullptr) const;
    // The motion's part along gravity from the accelerometers' filter (imu_vertical_deskew):
    // a copy of it carried from the scan's start through the sweep, the lidar at R_start then
    // turning with the gyro. Leaves the motion as it is when the filter is not ready or the IMU
    // does not cover the sweep.
    void VerticalFromImu(const Eigen::Matrix3d& R_start, int64_t stamp, ScanMotion* motion) const;
    // The sweep's correction prior for this scan (gyro or not).
    common::Vector6d CorrectionSigma(bool gyro) const;
    // The scan's duration: its largest time offset (1 ms at least).
    static double Duration(const common::PointCloud& scan);
    // The registration of result_ judged by its evidence (registration_check.hpp): sets
    // kCheckFailed and check_reasons (lidar_odometry_check.cpp).
    void JudgeScan(const Eigen::Isometry3d& T_pred, const Eigen::Isometry3d& T,
                   const common::Vector6d& sigma);

    // Now on the budget's clock (wall, or this thread's CPU time: cpu_time_budget).
    Clock::time_point BudgetClockNow() const {
        return BudgetNow(config_.registration.cpu_time_budget);
    }
    // Process's steps (the header's numbers), each on work_ and result_.
    void BeginScan(const common::PointCloud& scan);
    void Predict();  // 1: work_.delta and sigma
    void PreprocessScan(const common::PointCloud& cloud, const ScanMotion& motion);  // 2
    void ExtractEdges();        // the edge features of the deskewed points, when configured
    bool TooFewPoints() const;  // fewer registration points than registration needs
    // 3: from the prediction, the gyro's gate, other headings, a start in motion, deskew rounds.
    void Register();
    // One registration from `from`, step `step` of the scan: sets result_ and work_.T; false on
    // failure, or when the deadline stopped it before its first iteration (work_.cut): then
    // result_.registration is the one before, or, for the scan's first, a failure.
    bool Align(const Eigen::Isometry3d& from, BudgetStep step);
    // A registration of result_ that fails its checks without the gyro is done again from other
    // headings (RegistrationCheckConfig::retry_headings); result_ and work_.T become the first
    // passing one's, else stay the prediction's. Returns whether a registration holds.
    bool TryOtherHeadings();
    void RefineStart();  // the second scan of a start in motion (start_refinements)
    void DeskewAgain();  // rounds of deskewing with the estimated motion (max_deskew_rounds)
    // The next round's motion: the estimated one, a deskew_step of the way from the last.
    ScanMotion EstimatedMotion() const;
    // How far a motion e moves a point at the scene's extent (m): how far a prediction was off,
    // or a registration's start may be.
    double AtExtent(const Eigen::Isometry3d& e) const;
    // How far the predictions have been off (m, at the extent: the running mean of AtExtent's
    // squares, the adaptive threshold's sigma); none before 3 scans have measured it.
    std::optional<double> PredictionSigma() const;
    void UpdateMap();        // 4
    void UpdateVelocity();   // the pose kept, the constant velocity over the window
    void UpdateImuHeight();  // the accelerometers' filter learns what the scan saw of the height
    // The pose levelled by the gravity filter (imu_tilt) at the end of each of its windows.
    void LevelWithGravity();

    // One scan's values through the steps.
    struct ScanWork {
        const common::PointCloud* scan = nullptr;
        int64_t stamp = 0;
        double dt = 0;        // s since the previous scan (0 for the first)
        double duration = 0;  // the sweep's, s
        Eigen::Isometry3d T_prev = Eigen::Isometry3d::Identity();  // the previous scan's pose
        Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();   // the predicted motion
        Eigen::Isometry3d T_pred = Eigen::Isometry3d::Identity();  // T_prev * delta
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();       // the estimate so far
        common::Vector6d sigma = common::Vector6d::Zero();         // the prediction's
        ScanMotion motion;          // the one the scan is deskewed with
        bool gyro = false;          // the gyro covered the sweep
        bool pin_rotation = false;  // the gyro's rotation held (imu_rotation_gate)
        bool registered = false;    // a registration of this scan holds (result_.registration)
        bool cut = false;           // the last Align: stopped before its first iteration
        // m: how far the next Align's start may be off (AlignInput::prediction_error; 0: unknown)
        double start_error = 0;
        Clock::time_point deadline;  // on the budget's clock (BudgetClockNow)
        // On the budget's clock: the preprocessing's and the last registration's time, the cost
        // of a round of deskewing again before one was made.
        Clock::duration preprocess_time{}, align_time{};
    };
    const ImuMeasurement& Imu(size_t i) const { return imu_[(imu_head_ + i) % imu_.size()]; }

    LidarOdometryConfig config_;
    Preprocessor preprocessor_;
    VoxelMap map_;
    ScanRegistration registration_;
    MotionPrior body_prior_;
    ImuHeight imu_height_;
    GravityTilt gravity_tilt_;
    double last_height_share_ = 0;       // the last scan's axis_share (0: failed), for the deskew
    bool last_height_seen_ = true;       // whether the last scan saw the height (imu_height)
    bool last_height_from_imu_ = false;  // whether its predicted height was the filter's
    std::optional<EdgeExtractor> edge_extractor_;  // with edge_features
    std::optional<VoxelMap> edge_map_;
    std::span<const Eigen::Vector3f> edges_;  // of the last preprocessing
    std::vector<ImuMeasurement> imu_;         // ring buffer
    size_t imu_head_ = 0, imu_count_ = 0;
    std::vector<Eigen::Vector3f> world_points_;  // scratch: map points at the estimated pose
    common::PointCloud first_scan_;              // kept for a start in motion (step 3)
    double model_error_sq_ = 0;                  // mean of the squared prediction errors
    size_t model_error_count_ = 0;
    double extent_ = 0;  // the scene's extent (smoothed 90th range percentile), m

    OdometryResult result_;
    ScanWork work_;
    bool initialized_ = false;
    int64_t last_stamp_ns_ = 0;
    // The constant-velocity model: the twist per second (lidar frame) over the last
    // velocity_window scans, from the poses kept here.
    common::Vector6d velocity_ = common::Vector6d::Zero();
    struct PastPose {
        int64_t stamp_ns;
        Eigen::Isometry3d T_odom_lidar;
    };
    std::vector<PastPose> past_;  // ring of velocity_window + 1
    size_t past_count_ = 0;
    bool last_degenerate_ = false;  // the previous scan: degenerate or failed
    uint64_t dropped_inputs_ = 0;
    size_t scans_ = 0;
};

}  // namespace bimslam::odometry
