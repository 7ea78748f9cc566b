// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam bim info | mesh: what an IFC model holds, and its geometry as a PLY mesh with an element
// table beside it.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/ply.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/cli/command.hpp"

namespace bimslam::cli {
namespace {
namespace fs = std::filesystem;
using common::FileError;
using common::StatusCode;

struct BimOptions {
    std::string model;
    bool json = false;
    std::string out;
    bool all = false;
    std::string storey;
    bool no_railings = false;
};

struct Loaded {
    bim::BimModel model;
    double load_s = 0;
};

// Loads with a progress line on stderr when it is a terminal (big models take seconds).
Loaded Load(const std::string& file, bim::IfcLoadOptions options) {
    const bool tty = ::isatty(STDERR_FILENO) != 0;
    int shown = -1;
    if (tty) {
        options.progress = [&](double f) {
            const int percent = int(f * 100);
            if (percent == shown) return;
            shown = percent;
            std::cerr << "\rloading " << file << "  " << percent << "%" << std::flush;
        };
    }
    const auto t0 = std::chrono::steady_clock::now();
    Loaded out;
    try {
        out.model = bim::LoadIfc(file, options);
    } catch (...) {
        if (tty) std::cerr << "\r\033[K" << std::flush;
        throw;
    }
    out.load_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (tty) std::cerr << "\r\033[K" << std::flush;
    return out;
}

nlohmann::json Point(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }

std::string Metres(double v) {
    std::ostringstream s;
    s << std::fixed << std::setprecision(2) << v;
    return s.str();
}

nlohmann::json AssumedFloorsJson(const bim::BimModel& m) {
    nlohmann::json out = nlohmann::json::array();
    for (const bim::AssumedFloor& f : m.assumed_floors) {
        out.push_back({{"storey", m.storeys[size_t(f.storey)].name},
                       {"area_m2", f.area_m2},
                       {"stair_openings_m2", f.opening_m2}});
    }
    return out;
}

// "assumed     floors of 'Level 1' (1204 m2), 'Level 2' (1180 m2, 24 m2 left open over stairs):
// the file models none" when the ingest assumed any.
void PrintAssumedFloors(const bim::BimModel& m) {
    if (m.assumed_floors.empty()) return;
    std::cout << "assumed     floors of";
    for (size_t i = 0; i < m.assumed_floors.size(); ++i) {
        const bim::AssumedFloor& f = m.assumed_floors[i];
        std::cout << (i ? ", '" : " '") << m.storeys[size_t(f.storey)].name << "' ("
                  << std::lround(f.area_m2) << " m2";
        if (f.opening_m2 > 0) {
            std::cout << ", " << std::lround(f.opening_m2) << " m2 left open over stairs";
        }
        std::cout << ")";
    }
    std::cout << ": the file models none\n";
}

int Info(const BimOptions& o) {
    const Loaded loaded = Load(o.model, {});
    const bim::BimModel& m = loaded.model;
    const Eigen::AlignedBox3d box = m.Bounds();
    if (o.json) {
        nlohmann::json storeys = nlohmann::json::array();
        for (const auto& s : m.storeys) {
            storeys.push_back({{"name", s.name}, {"elevation_m", s.elevation_m}});
        }
        auto list = [](const std::vector<bim::FailedElement>& elements) {
            nlohmann::json out = nlohmann::json::array();
            for (const auto& f : elements) {
                out.push_back(
                    {{"global_id", f.global_id}, {"class", f.ifc_class}, {"reason", f.reason}});
            }
            return out;
        };
        const nlohmann::json j = {
            {"file", o.model},
            {"schema", m.schema},
            {"length_unit_m", m.length_unit_m},
            {"storeys", storeys},
            {"elements", m.class_counts},
            {"bbox_m", box.isEmpty() ? nlohmann::json(nullptr)
                                     : nlohmann::json{Point(box.min()), Point(box.max())}},
            {"failed", list(m.failed)},
            {"faces_reordered", m.faces_reordered},
            {"faces_lost", m.faces_lost},
            {"incomplete", list(m.incomplete)},
            {"triangles", m.mesh.triangles.size()},
            {"elements_with_geometry", m.elements.size()},
            {"assumed_floors", AssumedFloorsJson(m)},
            {"warnings", m.warning_count},
            {"load_s", loaded.load_s},
        };
        std::cout << j.dump(2) << "\n";
        return kExitOk;
    }
    size_t structure = 0;
    for (const auto& e : m.elements) structure += e.role == bim::ElementRole::kStructure;
    std::cout << "model       " << o.model << "\n"
              << "schema      " << m.schema << ", length unit " << m.length_unit_m << " m\n"
              << "storeys     " << m.storeys.size();
    for (size_t i = 0; i < m.storeys.size(); ++i) {
        std::cout << (i == 0 ? ": " : ", ") << "'" << m.storeys[i].name << "' "
                  << Metres(m.storeys[i].elevation_m) << " m";
    }
    std::cout << "\nelements    " << m.elements.size() << " with geometry (" << structure
              << " structure, " << m.elements.size() - structure << " transient), "
              << m.mesh.triangles.size() << " triangles\n";
    PrintAssumedFloors(m);
    std::cout << "classes    ";
    size_t column = 11;
    for (const auto& [cls, n] : m.class_counts) {
        const std::string item = " " + cls + " " + std::to_string(n);
        if (column + item.size() > 100) {
            std::cout << "\n           ";
            column = 11;
        }
        std::cout << item;
        column += item.size();
    }
    std::cout << "\n";
    if (box.isEmpty()) {
        std::cout << "bbox        none (no geometry)\n";
    } else {
        const Eigen::Vector3d size = box.sizes();
        std::cout << "bbox        " << Metres(box.min().x()) << " " << Metres(box.min().y()) << " "
                  << Metres(box.min().z()) << " .. " << Metres(box.max().x()) << " "
                  << Metres(box.max().y()) << " " << Metres(box.max().z()) << " m ("
                  << Metres(size.x()) << " x " << Metres(size.y()) << " x " << Metres(size.z())
                  << " m)\n";
    }
    std::cout << "failed      " << m.failed.size() << "\n";
    for (const auto& f : m.failed) {
        std::cout << "            " << f.ifc_class << " " << f.global_id << ": " << f.reason
                  << "\n";
    }
    std::cout << "faces       " << m.faces_reordered << " reordered (outer boundary put first), "
              << m.faces_lost << " lost (IFC++ could not triangulate them)\n";
    if (!m.incomplete.empty()) {
        std::cout << "incomplete  " << m.incomplete.size() << " elements lack faces\n";
        for (const auto& f : m.incomplete) {
            std::cout << "            " << f.ifc_class << " " << f.global_id << ": " << f.reason
                      << "\n";
        }
    }
    std::cout << "warnings    " << m.warning_count << "\n";
    constexpr size_t kShown = 10;
    for (size_t i = 0; i < m.warnings.size() && i < kShown; ++i) {
        std::cout << "            " << m.warnings[i] << "\n";
    }
    if (m.warnings.size() > kShown) {
        std::cout << "            ... (" << m.warning_count - kShown << " more)\n";
    }
    std::cout << "loaded in   " << std::fixed << std::setprecision(2) << loaded.load_s << " s\n";
    return kExitOk;
}

int Mesh(const BimOptions& o) {
    const fs::path out = o.out;
    const fs::path sidecar = fs::path(out).replace_extension(".json");
    if (sidecar == out) {
        throw FileError(StatusCode::kInvalidArgument, out.string(), 0,
                        "the mesh cannot be a .json file: the element table goes there");
    }
    bim::IfcLoadOptions options;
    options.railings_are_structure = !o.no_railings;
    const Loaded loaded = Load(o.model, options);
    const bim::BimModel& m = loaded.model;
    const int storey = o.storey.empty() ? -1 : bim::FindStorey(m, o.storey);
    const bim::BimModel kept = bim::SelectElements(m, [&](const bim::BimElement& e) {
        return (o.all || e.role == bim::ElementRole::kStructure) &&
               (storey < 0 || e.storey == storey);
    });

    io::PlyData ply;
    ply.vertices = kept.mesh.vertices;
    ply.triangles = kept.mesh.triangles;
    io::PlyProperty element{"element", io::PlyType::kUint32, {}};
    element.values.assign(ply.vertices.size(), 0.0);
    for (size_t t = 0; t < kept.mesh.triangles.size(); ++t) {
        for (const uint32_t v : kept.mesh.triangles[t])
            element.values[v] = kept.triangle_element[t];
    }
    ply.vertex_properties.push_back(std::move(element));
    io::WritePly(out, ply);

    nlohmann::json elements = nlohmann::json::array();
    for (size_t i = 0; i < kept.elements.size(); ++i) {
        const bim::BimElement& e = kept.elements[i];
        elements.push_back(
            {{"index", i},
             {"global_id", e.global_id},
             {"class", e.ifc_class},
             {"name", e.name},
             {"storey", e.storey >= 0 ? nlohmann::json(kept.storeys[size_t(e.storey)].name)
                                      : nlohmann::json(nullptr)},
             {"role", std::string(bim::ToString(e.role))},
             {"triangles", e.triangle_count}});
        if (e.assumed) elements.back()["assumed"] = true;  // not in the file (assumed_floors.hpp)
    }
    const nlohmann::json j = {{"model", o.model},
                              {"schema", kept.schema},
                              {"length_unit_m", kept.length_unit_m},
                              {"origin_m", Point(kept.origin_m)},
                              {"elements", elements}};
    io::WriteFileAtomic(sidecar, j.dump(2) + "\n");
    std::cout << "wrote " << out.string() << ": " << kept.elements.size() << " elements ("
              << (o.all ? "all with geometry" : "permanent structure")
              << (storey >= 0 ? ", storey '" + o.storey + "'" : std::string()) << "), "
              << kept.mesh.triangles.size() << " triangles, " << kept.mesh.vertices.size()
              << " vertices with their element index\n"
              << "wrote " << sidecar.string() << ": the element table";
    if (!kept.origin_m.isZero()) {
        std::cout << "; vertices are relative to origin_m " << kept.origin_m.transpose();
    }
    std::cout << "\n";
    if (!m.failed.empty()) {
        std::cout << "note: " << m.failed.size()
                  << " elements have no geometry (bimslam bim info lists them)\n";
    }
    return kExitOk;
}

}  // namespace

void AddBimCommands(CLI::App& bim, int& exit_code) {
    auto info_opt = std::make_shared<BimOptions>();
    CLI::App* info = bim.add_subcommand(
        "info",
        "Read an IFC model; print its storeys, element classes, extent and failures, the "
        "faces whose outer boundary was put first (listed after a hole) or that IFC++ lost, and "
        "the floors assumed where the file models none (host_tools/bim/README.md)");
    info->add_option("MODEL", info_opt->model, "IFC file (STEP, IFC2X3 or IFC4)")->required();
    info->add_flag("--json", info_opt->json, "machine-readable output");
    info->callback([info_opt, &exit_code] { exit_code = Run([&] { return Info(*info_opt); }); });

    auto mesh_opt = std::make_shared<BimOptions>();
    CLI::App* mesh = bim.add_subcommand(
        "mesh",
        "Write a model's geometry as a binary PLY mesh (metres, per-vertex uint32 'element') and "
        "its element table as JSON beside it (same name, .json)");
    mesh->add_option("MODEL", mesh_opt->model, "IFC file (STEP, IFC2X3 or IFC4)")->required();
    mesh->add_option("--out,-o", mesh_opt->out, "the PLY file to write")->required();
    mesh->add_flag("--all", mesh_opt->all,
                   "every element with geometry (default: the permanent structure only)");
    mesh->add_option("--storey", mesh_opt->storey, "only the elements of this storey (by name)");
    mesh->add_flag("--no-railings", mesh_opt->no_railings,
                   "railings are not structure (a LiDAR sees little of them)");
    mesh->callback([mesh_opt, &exit_code] { exit_code = Run([&] { return Mesh(*mesh_opt); }); });
}

}  // namespace bimslam::cli
