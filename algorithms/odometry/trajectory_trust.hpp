// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Whether a trajectory (replayed, or the rig's) can be trusted (issue 32, item 3): the scans whose
// registration failed (too few correspondences) or failed its own evidence (kCheckFailed,
// algorithms/odometry/registration_check.hpp) gathered into stretches, and a verdict for the run.
// A pose after a failed scan is only as good as the guess that scan kept, so the verdict is
// "untrusted" as soon as one stretch exists (a registration with too few correspondences, none
// within the budget, or a check failed on one the budget stopped, whose prediction came from the
// gyro or the legs excepted: bridged_by_prior); the stretches say where to
// look (and which part of the trajectory `bimslam map` must not present as good). Apart from
// them, the stretches where the scans did not see the height for longer than kMaxHeightUnseenS
// in a row (with the IMU, odometry::kHeightUnseen): the height there is the accelerometers' dead
// reckoning, said, not untrusted (anchoring the whole walk measured better than in pieces there:
// algorithms/odometry/README.md, "The height in stairwells"); and the same way, the runs of
// degenerate scans longer than kMaxDegenerateS, where some directions are the prediction's.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace bimslam::odometry {

struct FailedStretch {
    size_t first_scan = 0, last_scan = 0;  // 0-based scan indices, inclusive
    double first_s = 0, last_s = 0;        // seconds since the first scan
    int64_t first_ns = 0, last_ns = 0;     // the scans' stamps (sensor clock), as in the session
    size_t failed = 0;                     // failed scans in it
    uint32_t check_reasons = 0;            // odometry::CheckReason bits over its scans
    bool registration_failed = false;      // some scan had too few correspondences
    bool cut_by_budget = false;            // some scan's registration the budget stopped
    double seconds = 0;                    // height_unseen() and degenerate(): the run's length
};

// Runs of consecutive scans that carry one flag, kept once a run lasts longer than limit_s (the
// run then grows with its scans): TrajectoryTrust's height_unseen() and degenerate().
class FlagRuns {
public:
    explicit FlagRuns(double limit_s) : limit_s_(limit_s) {}
    void Add(bool flagged, size_t scan, double t_s, int64_t stamp_ns);
    const std::vector<FailedStretch>& runs() const { return runs_; }
    // The runs that overlap scans [first_scan, last_scan], with their stamps and seconds.
    nlohmann::json Json(size_t first_scan, size_t last_scan) const;
    // " scans a-b (x-y s), ..." for a person (at most 8).
    std::string Text() const;

private:
    double limit_s_;
    std::vector<FailedStretch> runs_;
    bool in_run_ = false;
    FailedStretch run_;  // the current run (first scan, time, stamp; last scan)
};

class TrajectoryTrust {
public:
    // Failed scans closer than merge_gap scans join one stretch.
    explicit TrajectoryTrust(size_t merge_gap = 10) : merge_gap_(merge_gap) {}

    // Every scan, in order: its index, seconds since the first scan, odometry flags and reasons,
    // and its stamp (the one trajectory.tum and times.txt carry).
    void Add(size_t scan, double t_s, uint32_t flags, uint32_t check_reasons, int64_t stamp_ns = 0);

    bool trusted() const { return stretches_.empty(); }
    // Scans whose registration found too few correspondences but whose prediction came from the
    // gyro or the legs: kept at that prediction, counted here, not untrusting the run.
    size_t bridged_by_prior() const { return bridged_; }
    // Scans the budget cut whose prediction came from the gyro or the legs: not registered within
    // the budget (kRegistrationFailed with kOverBudget), or whose check failed on a registration
    // the deadline stopped (kCheckFailed with kCutShort). Counted in bridged_by_prior too.
    size_t bridged_over_budget() const { return bridged_over_budget_; }
    const std::vector<FailedStretch>& stretches() const { return stretches_; }
    // The runs of scans blind to the height longer than kMaxHeightUnseenS (failed is 0).
    const std::vector<FailedStretch>& height_unseen() const { return blind_.runs(); }
    // The runs of degenerate scans (kDegenerate: some directions the prediction's) longer than
    // kMaxDegenerateS (failed is 0).
    const std::vector<FailedStretch>& degenerate() const { return degenerate_.runs(); }
    // The runs of scans that saw the height again while the accelerometers' was uncertain
    // (odometry::kHeightAmbiguous): the height there, and after, may be off by whole stair
    // risers. Said, as height_unseen(), not untrusting: anchoring corrects it against the model.
    const std::vector<FailedStretch>& height_ambiguous() const { return ambiguous_.runs(); }
    // "trusted" or "untrusted".
    std::string Verdict() const { return trusted() ? "trusted" : "untrusted"; }
    // One line for a person: what failed where, and where the height was not seen.
    std::string Describe() const;
    // {"verdict", "failed_stretches": [{first_scan, last_scan, first_s, last_s, failed,
    // reasons: [...]}], "height_unseen_stretches": [{..., seconds}], "degenerate_stretches" and
    // "height_ambiguous_stretches" the same way}.
    nlohmann::json ToJson() const;
    // The verdict a session of scans [first_scan, last_scan] carries (kSessionFile in its folder):
    // ToJson() of the stretches (and the height_unseen, degenerate, height_ambiguous ones) that
    // overlap those scans, with their stamps, so that anchoring can find the keyframes on either
    // side (host_tools/anchor/README.md, "Untrusted odometry").
    nlohmann::json SessionJson(size_t first_scan, size_t last_scan) const;

    // The file in a session folder that holds SessionJson().
    static constexpr const char* kSessionFile = "odometry_verdict.json";
    // Scans cut by the budget in a row that a measured prior bridges (Add): one spike of the
    // machine's load cuts one scan; a longer run is a failed stretch.
    static constexpr size_t kMaxBridgedCuts = 3;
    // Seconds in a row the scans may not see the height (odometry::kHeightUnseen) before the
    // run says so (height_unseen()). The accelerometers' height drifts by a t^2 / 2: a = 0.05 m/s^2
    // (a tilt error of 0.3 deg on a rig pitched 30 deg on a flight, and the sensor's bias turned
    // with it) gives 10 cm in 2 s. Office_A's stairwell: runs of 3.2 and 4.7 s ended flights
    // 34 and 40 cm off; runs up to 0.3 s, 2-4 cm.
    static constexpr double kMaxHeightUnseenS = 2.0;
    // Seconds in a row the scans may be degenerate (odometry::kDegenerate) before the run says so
    // (degenerate()). Along a degenerate direction the pose is the prediction's: the velocity
    // before the run (constant velocity; the legs' on a Go1), whose error grows as the change of
    // velocity times the time, so a walker's 0.1 m/s (a slower step, a landing's end of the
    // climb) gives 10 cm in 1 s. Office_A's stairwell (held out, stop 59): LiDAR-only runs of
    // 1.5-3.5 s on a flight, the walk 38.55 cm RMSE and called trusted with nothing said; none in
    // 33 walks of the other buildings.
    static constexpr double kMaxDegenerateS = 1.0;
    // Seconds in a row the gyro alone (no legs: hand-held) may bridge scans with too few
    // correspondences (Add). Its prediction turns the pose but moves it at the velocity before the
    // run, so its error grows as kMaxDegenerateS's does; past this the scans are failed. FZK-Haus's
    // attic (visits benchmark, held out): a hand-held walk bridged 80 scans in a row, 8 s at
    // 0.57 m/s while the walker went 1.0 m/s, and ended 79 cm RMSE (se3-aligned), called trusted.
    static constexpr double kMaxGyroBridgedS = 1.0;

private:
    size_t merge_gap_;
    std::vector<FailedStretch> stretches_;
    FlagRuns blind_{kMaxHeightUnseenS};     // height_unseen()
    FlagRuns degenerate_{kMaxDegenerateS};  // degenerate()
    FlagRuns ambiguous_{-1.0};              // height_ambiguous(): every run, one scan included
    size_t bridged_ = 0;
    size_t bridged_over_budget_ = 0;
    size_t cut_run_ = 0, last_cut_scan_ = 0;  // scans cut by the budget in a row, the last one
    // The run of scans the gyro alone bridged: its first scan's time, its last scan (none:
    // SIZE_MAX).
    double gyro_run_first_s_ = 0;
    size_t gyro_run_last_ = SIZE_MAX;

    std::string DescribeTrusted() const;
    std::string DescribeFailed() const;
    std::string DescribeRuns() const;
    // The stretch a problem at `scan` belongs to: the last one, or a new one from `first`.
    FailedStretch& StretchFor(size_t first, double first_s, int64_t first_ns, size_t scan);
};

}  // namespace bimslam::odometry
