// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/changes/element_check.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>

#include "algorithms/common/status.hpp"

namespace bimslam::changes {

std::string_view ToString(Verdict v) {
    switch (v) {
        case Verdict::kConfirmed:
            return "confirmed";
        case Verdict::kMissing:
            return "missing";
        case Verdict::kDeviating:
            return "deviating";
        case Verdict::kNotObserved:
            return "not_observed";
    }
    return "?";
}

std::string_view ToString(ToleranceVerdict v) {
    switch (v) {
        case ToleranceVerdict::kWithin:
            return "within";
        case ToleranceVerdict::kBeyond:
            return "beyond";
        case ToleranceVerdict::kNotObserved:
            return "not_observed";
    }
    return "?";
}

ToleranceVerdict JudgeTolerance(const ElementReport& report, const ElementCheckConfig& config) {
    switch (report.verdict) {
        case Verdict::kNotObserved:
            return ToleranceVerdict::kNotObserved;
        case Verdict::kMissing:  // not where the model has it, by its whole size
            return ToleranceVerdict::kBeyond;
        case Verdict::kConfirmed:
        case Verdict::kDeviating:
            break;
    }
    // A moved element stands elsewhere (or turned about its centre): beyond, whatever its
    // translation.
    if (report.moved) return ToleranceVerdict::kBeyond;
    if (report.support_points < config.min_support_points || report.constrained_axes == 0) {
        return ToleranceVerdict::kNotObserved;  // seen, but its deviation was not measured
    }
    return report.offset.norm() <= config.tolerance_m ? ToleranceVerdict::kWithin
                                                      : ToleranceVerdict::kBeyond;
}

void ElementCheckConfig::Validate() const {
    if (!(support_distance_m > 0)) common::ThrowInvalid("elements.support_distance_m must be > 0");
    if (!(deviation_tolerance_m > 0))
        common::ThrowInvalid("elements.deviation_tolerance_m must be > 0");
    if (!(tolerance_m > 0)) common::ThrowInvalid("elements.tolerance_m must be > 0");
    if (!(min_judged_area_m2 >= 0))
        common::ThrowInvalid("elements.min_judged_area_m2 must be >= 0");
    if (!(missing_seen_fraction >= 0 && missing_seen_fraction <= 1)) {
        common::ThrowInvalid("elements.missing_seen_fraction must be in [0, 1], not " +
                             std::to_string(missing_seen_fraction));
    }
    if (!(offset_cauchy_m > 0)) common::ThrowInvalid("elements.offset_cauchy_m must be > 0");
    if (!(min_constraint > 0)) common::ThrowInvalid("elements.min_constraint must be > 0");
}

std::vector<Eigen::Vector3f> FaceNormals(const common::TriangleMesh& mesh) {
    std::vector<Eigen::Vector3f> n(mesh.triangles.size(), Eigen::Vector3f::Zero());
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& tri = mesh.triangles[t];
        const Eigen::Vector3f c = (mesh.vertices[tri[1]] - mesh.vertices[tri[0]])
                                      .cross(mesh.vertices[tri[2]] - mesh.vertices[tri[0]]);
        if (c.norm() > 0) n[t] = c.normalized();
    }
    return n;
}

OffsetFit FitOffset(std::span<const float> r, std::span<const Eigen::Vector3f> n, double cauchy_m,
                    double min_constraint) {
    OffsetFit fit;
    if (r.empty()) return fit;
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    const double c2 = cauchy_m * cauchy_m;
    for (int iteration = 0; iteration < 8; ++iteration) {
        Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
        Eigen::Vector3d b = Eigen::Vector3d::Zero();
        for (size_t i = 0; i < r.size(); ++i) {
            const Eigen::Vector3d ni = n[i].cast<double>();
            const double res = double(r[i]) - ni.dot(t);
            const double w = 1.0 / (1.0 + res * res / c2);
            A += w * ni * ni.transpose();
            b += w * ni * double(r[i]);
        }
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(A);
        const double largest = eig.eigenvalues().maxCoeff();
        Eigen::Vector3d next = Eigen::Vector3d::Zero();
        int axes = 0;
        for (int k = 0; k < 3; ++k) {
            const double lambda = eig.eigenvalues()[k];
            if (lambda < std::max(min_constraint, 0.05 * largest)) continue;
            const Eigen::Vector3d v = eig.eigenvectors().col(k);
            next += v * (v.dot(b) / lambda);
            ++axes;
        }
        fit.constrained_axes = axes;
        const bool converged = (next - t).norm() < 1e-5;
        t = next;
        if (converged) break;
    }
    double sum2 = 0;
    for (size_t i = 0; i < r.size(); ++i) {
        const double res = double(r[i]) - n[i].cast<double>().dot(t);
        sum2 += res * res;
    }
    fit.offset = t;
    fit.residual_rms_m = std::sqrt(sum2 / double(r.size()));
    return fit;
}

std::vector<std::vector<uint32_t>> ElementSupport(const ChangeModel& model,
                                                  std::span<const float> signed_m,
                                                  std::span<const uint32_t> triangle,
                                                  std::span<const uint8_t> usable,
                                                  double distance) {
    if (signed_m.size() != triangle.size() || usable.size() != triangle.size()) {
        common::ThrowInvalid("elements.ElementSupport: inputs of different sizes");
    }
    std::vector<std::vector<uint32_t>> support(model.element_count());
    const float limit = float(distance);
    for (size_t i = 0; i < triangle.size(); ++i) {
        if (!usable[i] || triangle[i] == kNoElement || !(std::abs(signed_m[i]) <= limit)) continue;
        support[model.triangle_element[triangle[i]]].push_back(uint32_t(i));
    }
    return support;
}

std::vector<ElementReport> CheckElements(const ChangeModel& model, std::span<const float> signed_m,
                                         std::span<const uint32_t> triangle,
                                         const std::vector<std::vector<uint32_t>>& support,
                                         std::span<const ElementEvidence> evidence,
                                         const ElementCheckConfig& config) {
    config.Validate();
    const size_t elements = model.element_count();
    if (evidence.size() != elements || support.size() != elements ||
        signed_m.size() != triangle.size()) {
        common::ThrowInvalid("elements.CheckElements: inputs of different sizes");
    }
    const std::vector<Eigen::Vector3f> normals = FaceNormals(model.mesh);
    std::vector<ElementReport> out(elements);
    std::vector<float> r;
    std::vector<Eigen::Vector3f> n;
    for (size_t e = 0; e < elements; ++e) {
        ElementReport& rep = out[e];
        rep.evidence = evidence[e];
        rep.support_points = support[e].size();
        r.clear();
        n.clear();
        double sum = 0, sum2 = 0;
        for (const uint32_t i : support[e]) {
            const float s = signed_m[i];
            r.push_back(s);
            n.push_back(normals[triangle[i]]);
            sum += s;
            sum2 += double(s) * s;
            if (std::abs(s) > std::abs(rep.max_signed_m)) rep.max_signed_m = s;
        }
        if (!r.empty()) {
            rep.mean_signed_m = sum / double(r.size());
            rep.rms_m = std::sqrt(sum2 / double(r.size()));
            const OffsetFit fit = FitOffset(r, n, config.offset_cauchy_m, config.min_constraint);
            rep.offset = fit.offset;
            rep.constrained_axes = fit.constrained_axes;
            rep.residual_rms_m = fit.residual_rms_m;
        }
        const bool supported = rep.support_points >= config.min_support_points;
        const bool off = supported && rep.offset.norm() >= config.deviation_tolerance_m;
        if (!model.Judged(e)) {
            rep.verdict = Verdict::kNotObserved;  // beams pass it, or it is assumed: not judged
        } else if (rep.evidence.expected_area_m2 < config.min_judged_area_m2) {
            rep.verdict = Verdict::kNotObserved;
        } else if (rep.evidence.seen_area_m2 <
                   config.missing_seen_fraction * rep.evidence.expected_area_m2) {
            rep.verdict = Verdict::kMissing;
        } else {
            rep.verdict = off ? Verdict::kDeviating : Verdict::kConfirmed;
        }
    }
    return out;
}

}  // namespace bimslam::changes
