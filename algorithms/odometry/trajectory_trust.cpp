// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/odometry/trajectory_trust.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <utility>

#include "algorithms/odometry/lidar_odometry.hpp"

namespace bimslam::odometry {
namespace {

std::vector<std::string> Reasons(const FailedStretch& s) {
    std::vector<std::string> out;
    if (s.registration_failed) out.push_back("registration failed");
    if (s.cut_by_budget) out.push_back("cut by the budget");
    for (const uint32_t bit : {kLowOverlap, kFewInliers, kHighResidual, kFarFromPrediction}) {
        if (s.check_reasons & bit) out.push_back(CheckReasonText(bit));
    }
    return out;
}

// Where a stretch is: its scans, seconds since the first scan and stamps (a session's files').
nlohmann::json Where(const FailedStretch& s) {
    return {{"first_scan", s.first_scan},   {"last_scan", s.last_scan},
            {"first_s", s.first_s},         {"last_s", s.last_s},
            {"first_stamp_ns", s.first_ns}, {"last_stamp_ns", s.last_ns}};
}

}  // namespace

FailedStretch& TrajectoryTrust::StretchFor(size_t first, double first_s, int64_t first_ns,
                                           size_t scan) {
    if (stretches_.empty() || first > stretches_.back().last_scan + merge_gap_) {
        FailedStretch s;
        s.first_scan = first;
        s.first_s = first_s;
        s.first_ns = first_ns;
        stretches_.push_back(s);
    }
    FailedStretch& s = stretches_.back();
    if (first < s.first_scan) {  // a run blind to the height that began before a failed scan
        s.first_scan = first;
        s.first_s = first_s;
        s.first_ns = first_ns;
    }
    s.last_scan = std::max(s.last_scan, scan);
    return s;
}

void FlagRuns::Add(bool flagged, size_t scan, double t_s, int64_t stamp_ns) {
    if (!flagged) {
        in_run_ = false;
        return;
    }
    if (!in_run_ || scan != run_.last_scan + 1) {
        in_run_ = true;
        run_ = FailedStretch{};
        run_.first_scan = scan;
        run_.first_s = t_s;
        run_.first_ns = stamp_ns;
    }
    run_.last_scan = scan;
    run_.last_s = t_s;
    run_.last_ns = stamp_ns;
    run_.seconds = t_s - run_.first_s;
    if (run_.seconds <= limit_s_) return;
    if (runs_.empty() || runs_.back().first_scan != run_.first_scan) runs_.push_back(run_);
    runs_.back() = run_;
}

nlohmann::json FlagRuns::Json(size_t first_scan, size_t last_scan) const {
    nlohmann::json list = nlohmann::json::array();
    for (const FailedStretch& b : runs_) {
        if (b.last_scan < first_scan || b.first_scan > last_scan) continue;
        nlohmann::json run = Where(b);
        run["seconds"] = b.seconds;
        list.push_back(std::move(run));
    }
    return list;
}

std::string FlagRuns::Text() const {
    std::string text;
    char buf[96];
    for (size_t k = 0; k < runs_.size() && k < 8; ++k) {
        const FailedStretch& b = runs_[k];
        std::snprintf(buf, sizeof buf, " scans %zu-%zu (%.1f-%.1f s)%s", b.first_scan, b.last_scan,
                      b.first_s, b.last_s, k + 1 < runs_.size() ? "," : "");
        text += buf;
    }
    if (runs_.size() > 8) text += " ...";
    return text;
}

void TrajectoryTrust::Add(size_t scan, double t_s, uint32_t flags, uint32_t check_reasons,
                          int64_t stamp_ns) {
    blind_.Add((flags & odometry::kHeightUnseen) != 0, scan, t_s, stamp_ns);
    degenerate_.Add((flags & odometry::kDegenerate) != 0, scan, t_s, stamp_ns);
    ambiguous_.Add((flags & odometry::kHeightAmbiguous) != 0, scan, t_s, stamp_ns);
    const bool reg_failed = (flags & odometry::kRegistrationFailed) != 0;
    const bool check_failed = (flags & odometry::kCheckFailed) != 0;
    if (!reg_failed && !check_failed) return;
    // Too few correspondences keeps the prediction. With the gyro or the Go1's legs behind it
    // that is the designed fallback, as along a degenerate direction: a few such scans in a
    // changed building left the map test's walk at 2.9 cm. Counted, not untrusted. Without a
    // measured prior it is a constant-velocity guess, and a scan that failed its own evidence
    // is never bridged.
    // A check failed on a registration the budget stopped (kCutShort) judged an unfinished one,
    // from a measured prediction: bridged the same way, and counted as cut, up to
    // kMaxBridgedCuts scans in a row. More in a row is the prediction's dead reckoning, a budget
    // the odometry does not fit (at --budget-ms 1 the demo's walk had 1164 of 2086 scans cut).
    const bool cut_short = check_failed && (flags & odometry::kCutShort) != 0;
    const bool cut = cut_short || (reg_failed && (flags & odometry::kOverBudget) != 0);
    if (cut) {
        cut_run_ = (cut_run_ > 0 && scan == last_cut_scan_ + 1) ? cut_run_ + 1 : 1;
        last_cut_scan_ = scan;
    }
    // The gyro alone turns the pose and keeps the velocity: kMaxGyroBridgedS in a row at most.
    const bool legs = (flags & odometry::kBodyPriorUsed) != 0;
    const bool gyro = !legs && (flags & odometry::kImuUsed) != 0;
    if (gyro) {
        const bool next = gyro_run_last_ != SIZE_MAX && scan == gyro_run_last_ + 1;
        if (!next) gyro_run_first_s_ = t_s;
        gyro_run_last_ = scan;
    } else {
        gyro_run_last_ = SIZE_MAX;
    }
    const bool within = legs || (gyro && t_s - gyro_run_first_s_ <= kMaxGyroBridgedS);
    if (((reg_failed && !check_failed) || cut_short) && (!cut || cut_run_ <= kMaxBridgedCuts) &&
        within) {
        ++bridged_;
        bridged_over_budget_ += cut ? 1 : 0;
        return;
    }
    FailedStretch& s = StretchFor(scan, t_s, stamp_ns, scan);
    s.last_s = t_s;
    s.last_ns = stamp_ns;
    ++s.failed;
    s.check_reasons |= check_reasons;
    s.registration_failed = s.registration_failed || reg_failed;
    s.cut_by_budget = s.cut_by_budget || cut;
}

std::string TrajectoryTrust::Describe() const {
    return (trusted() ? DescribeTrusted() : DescribeFailed()) + DescribeRuns();
}

std::string TrajectoryTrust::DescribeTrusted() const {
    // A bridged scan is no failed check, but a reader who sees `failed` > 0 beside "trusted"
    // must learn why.
    if (bridged_ == 0) return "trusted: every registration passed its checks";
    return "trusted: every registration passed its checks; " + std::to_string(bridged_) +
           " scans with too few correspondences kept the gyro's or the legs' prediction" +
           (bridged_over_budget_ == 0
                ? std::string()
                : " (" + std::to_string(bridged_over_budget_) + " of them cut by the budget)");
}

std::string TrajectoryTrust::DescribeFailed() const {
    size_t failed = 0;
    for (const FailedStretch& s : stretches_) failed += s.failed;
    std::string text = "UNTRUSTED: " + std::to_string(failed) + " failed scans in " +
                       std::to_string(stretches_.size()) + " stretches:";
    char buf[160];
    for (size_t k = 0; k < stretches_.size() && k < 8; ++k) {
        const FailedStretch& s = stretches_[k];
        std::string why;
        for (const std::string& r : Reasons(s)) why += (why.empty() ? "" : ", ") + r;
        std::snprintf(buf, sizeof buf, " scans %zu-%zu (%.1f-%.1f s, %zu failed: %s)%s",
                      s.first_scan, s.last_scan, s.first_s, s.last_s, s.failed, why.c_str(),
                      k + 1 < stretches_.size() ? ";" : "");
        text += buf;
    }
    if (stretches_.size() > 8) text += " ... (--json lists them all)";
    return text;
}

std::string TrajectoryTrust::DescribeRuns() const {
    std::string text;
    if (!blind_.runs().empty()) {
        text += "; the height not seen for over " + std::to_string(int(kMaxHeightUnseenS)) +
                " s (the accelerometers' alone) at" + blind_.Text();
    }
    if (!degenerate_.runs().empty()) {
        text += "; degenerate for over " + std::to_string(int(kMaxDegenerateS)) +
                " s (some directions the prediction's) at" + degenerate_.Text();
    }
    if (!ambiguous_.runs().empty()) {
        text +=
            "; the height seen again while the accelerometers' was uncertain (it may be off "
            "by whole stair risers from there on) at" +
            ambiguous_.Text();
    }
    return text;
}

nlohmann::json TrajectoryTrust::ToJson() const {
    nlohmann::json list = nlohmann::json::array();
    for (const FailedStretch& s : stretches_) {
        list.push_back({{"first_scan", s.first_scan},
                        {"last_scan", s.last_scan},
                        {"first_s", s.first_s},
                        {"last_s", s.last_s},
                        {"failed", s.failed},
                        {"reasons", Reasons(s)}});
    }
    return {{"verdict", Verdict()},
            {"failed_stretches", list},
            {"bridged_by_prior", bridged_},
            {"bridged_over_budget", bridged_over_budget_},
            {"height_unseen_stretches", blind_.Json(0, SIZE_MAX)},
            {"degenerate_stretches", degenerate_.Json(0, SIZE_MAX)},
            {"height_ambiguous_stretches", ambiguous_.Json(0, SIZE_MAX)}};
}

nlohmann::json TrajectoryTrust::SessionJson(size_t first_scan, size_t last_scan) const {
    nlohmann::json list = nlohmann::json::array();
    for (const FailedStretch& s : stretches_) {
        if (s.last_scan < first_scan || s.first_scan > last_scan) continue;
        nlohmann::json stretch = Where(s);
        stretch["failed"] = s.failed;
        stretch["reasons"] = Reasons(s);
        list.push_back(std::move(stretch));
    }
    return {{"format", "bimslam-odometry-verdict"},
            {"version", 1},
            {"verdict", list.empty() ? "trusted" : "untrusted"},
            {"first_scan", first_scan},
            {"last_scan", last_scan},
            {"failed_stretches", list},
            {"height_unseen_stretches", blind_.Json(first_scan, last_scan)},
            {"degenerate_stretches", degenerate_.Json(first_scan, last_scan)},
            {"height_ambiguous_stretches", ambiguous_.Json(first_scan, last_scan)}};
}

}  // namespace bimslam::odometry
