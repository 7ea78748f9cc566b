// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam rig-map: the rig's map package of a model (issue 35, item 1;
// algorithms/localization/README.md).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"
#include "algorithms/common/stopwatch.hpp"
#include "algorithms/common/utc_time.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/io/sha256.hpp"
#include "host_tools/anchor/rig_map_package.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/reference_session.hpp"
#include "host_tools/cli/command.hpp"

namespace bimslam::cli {
namespace {
namespace fs = std::filesystem;
using common::FileError;
using common::StatusCode;

struct RigMapArgs {
    std::string model;
    std::string out;
    std::string reference;
    bool overwrite = false;
    bool json = false;
};

// A reference given by the user must come from this very model (its session.json's SHA-256).
void CheckRigMapReference(const fs::path& reference, const std::string& model,
                          const std::string& sha) {
    io::SessionReadOptions ro;
    ro.load_clouds = false;
    ro.allow_recovery = false;
    const io::SessionManifest m = io::ReadSession(reference, ro).manifest;
    const std::string manifest_file = (reference / "session.json").string();
    if (!m.model) {
        throw FileError(StatusCode::kInvalidArgument, manifest_file, 0,
                        "not a BIM reference session (no model): make one with `bimslam "
                        "bim2session`, or leave out --reference");
    }
    if (m.model->sha256 != sha) {
        throw FileError(StatusCode::kInvalidArgument, manifest_file, 0,
                        "made from another model (" + m.model->file + ", SHA-256 " +
                            m.model->sha256 + "), not " + model + " (SHA-256 " + sha + ")");
    }
}

std::vector<localization::RigMapStorey> RigMapStoreys(const bim::BimModel& model) {
    std::vector<localization::RigMapStorey> out;
    for (const bim::BimStorey& s : model.storeys)
        out.push_back({s.name, s.global_id, s.elevation_m});
    std::stable_sort(out.begin(), out.end(),
                     [](const auto& a, const auto& b) { return a.elevation_m < b.elevation_m; });
    return out;
}

// The model's IfcSpaces for the package: each one's horizontal faces projected on x y (its
// footprint, floor and ceiling alike) and its heights, named by its LongName, else its Name.
std::vector<localization::RigMapSpace> RigMapSpaces(const bim::BimModel& model) {
    std::vector<localization::RigMapSpace> out;
    const common::TriangleMesh& mesh = model.mesh;
    for (const bim::BimElement& el : model.elements) {
        if (!el.ifc_class.starts_with("IfcSpace") || el.triangle_count == 0) continue;
        localization::RigMapSpace s;
        s.name = el.long_name.empty() ? el.name : el.long_name;
        s.global_id = el.global_id;
        s.storey = el.storey;
        s.z_min = std::numeric_limits<float>::max();
        s.z_max = std::numeric_limits<float>::lowest();
        for (uint32_t t = el.first_triangle; t < el.first_triangle + el.triangle_count; ++t) {
            const auto& tri = mesh.triangles[t];
            const Eigen::Vector3f &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]],
                                  &c = mesh.vertices[tri[2]];
            for (const Eigen::Vector3f* v : {&a, &b, &c}) {
                s.z_min = std::min(s.z_min, v->z());
                s.z_max = std::max(s.z_max, v->z());
            }
            const Eigen::Vector3f n = (b - a).cross(c - a);
            if (std::abs(n.z()) < 0.5f * n.norm()) continue;  // a wall's face
            for (const Eigen::Vector3f* v : {&a, &b, &c}) s.triangles.push_back(v->head<2>());
        }
        if (!s.triangles.empty()) out.push_back(std::move(s));
    }
    return out;
}

int MakePackage(const RigMapArgs& a) {
    const auto t0 = std::chrono::steady_clock::now();
    if (fs::exists(a.out) && !a.overwrite) {
        throw FileError(StatusCode::kAlreadyExists, a.out, 0, "exists (--overwrite replaces it)");
    }
    bim::IfcLoadOptions load;
    load.space_geometry = true;  // the package's spaces; the reference casts structure only
    const bim::BimModel model = bim::LoadIfc(a.model, load);
    const std::string sha = io::Sha256File(a.model);
    fs::path reference = a.reference;
    fs::path made;  // a reference made here, removed at the end
    if (!a.reference.empty()) {
        CheckRigMapReference(reference, a.model, sha);
    } else {
        made = fs::path(a.out).string() + ".reference.tmp." + std::to_string(::getpid());
        bim::ReferenceSessionOptions o;
        o.overwrite = true;
        bim::WriteReferenceSession(model, sha, made, o);
        reference = made;
    }
    localization::RigMap map;
    try {
        map = anchor::MakeRigMap(reference, RigMapStoreys(model));
    } catch (...) {
        if (!made.empty()) fs::remove_all(made);
        throw;
    }
    if (!made.empty()) {
        fs::remove_all(made);
        map.reference = "made from the model by bimslam rig-map";
    }
    map.spaces = RigMapSpaces(model);
    map.created = common::FormatUtcTime(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                            std::chrono::system_clock::now().time_since_epoch())
                                            .count());
    localization::WriteRigMap(a.out, map);
    const double bytes = double(fs::file_size(a.out));
    // Per level: surfels, and those the reference's own rays pass through (porous: a railing's
    // bars, registration/free_space.hpp), which the free-space check does not count.
    std::vector<size_t> surfels, porous;
    for (const auto& l : map.levels) {
        surfels.push_back(l.size());
        porous.push_back(size_t(std::count_if(l.surfels().begin(), l.surfels().end(),
                                              [](const auto& s) { return s.porous; })));
    }
    std::cout << "rig map  " << a.out << ": " << map.keyframes.size() << " keyframes on "
              << map.storeys.size() << " storeys, " << map.spaces.size() << " spaces, surfels";
    for (size_t l = 0; l < surfels.size(); ++l) {
        std::cout << (l ? " / " : " ") << surfels[l] << " at "
                  << Fixed(map.levels[l].config().voxel_size, 2) << " m";
        if (porous[l]) std::cout << " (" << porous[l] << " porous)";
    }
    std::cout << ", " << Fixed(bytes / 1e6, 1) << " MB in " << Fixed(common::SecondsSince(t0), 1)
              << " s\nmodel    " << map.model_file << " (SHA-256 " << map.model_sha256 << ")\n";
    if (a.json) {
        nlohmann::json j = {{"package", a.out},
                            {"bytes", size_t(bytes)},
                            {"keyframes", map.keyframes.size()},
                            {"storeys", map.storeys.size()},
                            {"spaces", map.spaces.size()},
                            {"surfels", surfels},
                            {"porous_surfels", porous},
                            {"model_file", map.model_file},
                            {"model_sha256", map.model_sha256},
                            {"reference", map.reference}};
        std::cout << j.dump(2) << "\n";
    }
    return kExitOk;
}

}  // namespace

void AddRigMapCommand(CLI::App& app, int& exit_code) {
    auto a = std::make_shared<RigMapArgs>();
    auto* cmd = app.add_subcommand(
        "rig-map",
        "The rig's map package of a model: the BIM reference's keyframes (poses, storeys, Scan "
        "Context descriptors) and the surfel pyramid the anchoring registers to (its surfels that "
        "the reference's own rays pass through, a railing's bars, marked porous: no evidence "
        "against a placement), the storeys, and "
        "the model's name and SHA-256, in one versioned, checksummed file for relocalising in the "
        "model on board (algorithms/localization/README.md)");
    cmd->add_option("MODEL", a->model, "IFC model (IFC2X3 or IFC4)")->required();
    cmd->add_option("--out,-o", a->out, "package file to write (e.g. office.rigmap)")->required();
    cmd->add_option("--reference", a->reference,
                    "the model's reference session (bimslam bim2session, or bimslam map's "
                    "OUT/reference) instead of simulating one; it must come from MODEL");
    cmd->add_flag("--overwrite", a->overwrite, "replace an existing package");
    cmd->add_flag("--json", a->json, "also print the figures as JSON");
    cmd->callback([a, &exit_code] { exit_code = Run([&] { return MakePackage(*a); }); });
}

}  // namespace bimslam::cli
