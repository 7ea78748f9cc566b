// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/odometry/trajectory_trust.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>

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

void TrajectoryTrust::AddHeightUnseen(size_t scan, double t_s, int64_t stamp_ns) {
    if (!unseen_run_ || scan != unseen_last_ + 1) {
        unseen_run_ = true;
        unseen_first_ = scan;
        unseen_first_s_ = t_s;
        unseen_first_ns_ = stamp_ns;
    }
    unseen_last_ = scan;
    const double run_s = t_s - unseen_first_s_;
    if (run_s <= kMaxHeightUnseenS) return;
    if (blind_.empty() || blind_.back().first_scan != unseen_first_) {
        FailedStretch b;
        b.first_scan = unseen_first_;
        b.first_s = unseen_first_s_;
        b.first_ns = unseen_first_ns_;
        blind_.push_back(b);
    }
    FailedStretch& b = blind_.back();
    b.last_scan = scan;
    b.last_s = t_s;
    b.last_ns = stamp_ns;
    b.height_unseen_s = run_s;
}

void TrajectoryTrust::Add(size_t scan, double t_s, uint32_t flags, uint32_t check_reasons,
                          int64_t stamp_ns) {
    if (flags & odometry::kHeightUnseen) {
        AddHeightUnseen(scan, t_s, stamp_ns);
    } else {
        unseen_run_ = false;
    }
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
    if (((reg_failed && !check_failed) || cut_short) && (!cut || cut_run_ <= kMaxBridgedCuts) &&
        (flags & (odometry::kImuUsed | odometry::kBodyPriorUsed)) != 0) {
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
    return (trusted() ? DescribeTrusted() : DescribeFailed()) + DescribeBlind();
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

std::string TrajectoryTrust::DescribeBlind() const {
    if (blind_.empty()) return "";
    std::string text = "; the height not seen for over " + std::to_string(int(kMaxHeightUnseenS)) +
                       " s (the accelerometers' alone) at";
    char buf[96];
    for (size_t k = 0; k < blind_.size() && k < 8; ++k) {
        const FailedStretch& b = blind_[k];
        std::snprintf(buf, sizeof buf, " scans %zu-%zu (%.1f-%.1f s)%s", b.first_scan, b.last_scan,
                      b.first_s, b.last_s, k + 1 < blind_.size() ? "," : "");
        text += buf;
    }
    if (blind_.size() > 8) text += " ...";
    return text;
}

nlohmann::json TrajectoryTrust::BlindJson(size_t first_scan, size_t last_scan) const {
    nlohmann::json list = nlohmann::json::array();
    for (const FailedStretch& b : blind_) {
        if (b.last_scan < first_scan || b.first_scan > last_scan) continue;
        list.push_back({{"first_scan", b.first_scan},
                        {"last_scan", b.last_scan},
                        {"first_s", b.first_s},
                        {"last_s", b.last_s},
                        {"first_stamp_ns", b.first_ns},
                        {"last_stamp_ns", b.last_ns},
                        {"seconds", b.height_unseen_s}});
    }
    return list;
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
            {"height_unseen_stretches", BlindJson(0, SIZE_MAX)}};
}

nlohmann::json TrajectoryTrust::SessionJson(size_t first_scan, size_t last_scan) const {
    nlohmann::json list = nlohmann::json::array();
    for (const FailedStretch& s : stretches_) {
        if (s.last_scan < first_scan || s.first_scan > last_scan) continue;
        list.push_back({{"first_scan", s.first_scan},
                        {"last_scan", s.last_scan},
                        {"first_s", s.first_s},
                        {"last_s", s.last_s},
                        {"first_stamp_ns", s.first_ns},
                        {"last_stamp_ns", s.last_ns},
                        {"failed", s.failed},
                        {"reasons", Reasons(s)}});
    }
    return {{"format", "bimslam-odometry-verdict"},
            {"version", 1},
            {"verdict", list.empty() ? "trusted" : "untrusted"},
            {"first_scan", first_scan},
            {"last_scan", last_scan},
            {"failed_stretches", list},
            {"height_unseen_stretches", BlindJson(first_scan, last_scan)}};
}

}  // namespace bimslam::odometry
