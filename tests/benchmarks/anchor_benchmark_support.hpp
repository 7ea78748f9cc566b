// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// What the anchoring benchmarks share (anchor_benchmark.cpp, storeys_benchmark.cpp): a building
// with its BIM reference session, APE with no alignment, and the spread of a figure over runs.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "algorithms/io/session.hpp"
#include "algorithms/io/sha256.hpp"
#include "algorithms/io/trajectory.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/reference_session.hpp"
#include "host_tools/bim/sample_building.hpp"
#include "host_tools/evaluation/trajectory_metrics.hpp"

namespace bimslam::bench {
namespace fs = std::filesystem;

struct Building {
    std::string name;
    fs::path ifc, reference;
    bim::BimModel model;
    std::vector<Eigen::Isometry3d> reference_poses;
};

// A building from an IFC file (a real model of ../shared/data) and its reference session.
inline Building ReferenceOf(const fs::path& dir, const std::string& name, const fs::path& ifc,
                            double keyframe_gap = 1.0) {
    Building b;
    b.name = name;
    b.ifc = ifc;
    b.model = bim::LoadIfc(b.ifc);
    b.reference = dir / (name + "_reference");
    bim::ReferenceSessionOptions ro;
    ro.keyframe_gap_m = keyframe_gap;
    ro.overwrite = true;
    bim::WriteReferenceSession(b.model, io::Sha256File(b.ifc), b.reference, ro);
    for (const auto& kf : io::ReadSession(b.reference, {.load_clouds = false}).keyframes) {
        b.reference_poses.push_back(kf.T_world_lidar);
    }
    return b;
}

// The sample building of `layout` (with its doors to the outside when `entrances`), written as
// IFC4 in `dir`, and its reference session.
inline Building MakeBuilding(const fs::path& dir, const std::string& name,
                             bim::BuildingLayout layout, bool entrances,
                             double keyframe_gap = 1.0) {
    fs::create_directories(dir);
    bim::SampleBuildingOptions o;
    o.layout = layout;
    o.exterior_doors = entrances;
    bim::WriteSampleBuilding(dir / (name + ".ifc"), o);
    return ReferenceOf(dir, name, dir / (name + ".ifc"), keyframe_gap);
}

struct Accuracy {
    double rmse_cm = NAN, max_cm = NAN, rot_rmse_deg = NAN, rot_max_deg = NAN;
};

inline Accuracy Ape(const std::vector<io::StampedPose>& est,
                    const std::vector<io::StampedPose>& truth) {
    evaluation::EvaluationConfig c;
    c.align = evaluation::Alignment::kNone;
    Accuracy a;
    try {
        const auto e = evaluation::Evaluate(est, truth, c);
        a = {100 * e.ape_trans_m.rmse, 100 * e.ape_trans_m.max, e.ape_rot_deg.rmse,
             e.ape_rot_deg.max};
    } catch (const std::exception&) {
    }
    return a;
}

inline void Spread(const char* what, std::vector<double> v) {
    v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return std::isnan(x); }), v.end());
    if (v.empty()) return;
    std::sort(v.begin(), v.end());
    const auto at = [&](double p) { return v[size_t(p * double(v.size() - 1) + 0.5)]; };
    std::printf("  %-28s min %6.2f  p10 %6.2f  median %6.2f  p90 %6.2f  max %6.2f  (%zu)\n", what,
                v.front(), at(0.1), at(0.5), at(0.9), v.back(), v.size());
}

// The suites named on the command line (arguments not starting with '-': ctest passes
// --benchmark_min_time), or `defaults` when none is; wants("name") says whether to run one.
class Suites {
public:
    Suites(int argc, char** argv, std::vector<std::string> defaults) {
        for (int i = 1; i < argc; ++i) {
            if (argv[i][0] != '-') names_.push_back(argv[i]);
        }
        if (names_.empty()) names_ = std::move(defaults);
    }
    bool operator()(const char* name) const {
        return std::find(names_.begin(), names_.end(), name) != names_.end();
    }

private:
    std::vector<std::string> names_;
};

}  // namespace bimslam::bench
