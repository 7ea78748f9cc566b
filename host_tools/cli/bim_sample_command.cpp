// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam bim sample: writes one of the project's own sample buildings (the two-storey office, the
// three-storey hall, the mirror-symmetric building, the long wing;
// host_tools/bim/sample_building.hpp) as an IFC4 file, and says what it holds.
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "algorithms/common/status.hpp"
#include "host_tools/bim/sample_building.hpp"
#include "host_tools/cli/command.hpp"

namespace bimslam::cli {
namespace {
namespace fs = std::filesystem;

struct SampleOptions {
    std::string out;
    std::string layout = "office";
    std::string unit = "m";
    uint64_t seed = 1;
    bool no_furniture = false;
    bool exterior_doors = false;
    int storeys = 0;
    bool force = false;
};

int Sample(const SampleOptions& o) {
    const fs::path path = o.out;
    if (fs::exists(path) && !o.force) {
        throw common::FileError(common::StatusCode::kAlreadyExists, path.string(), 0,
                                "exists; pass --force to overwrite it");
    }
    bim::SampleBuildingOptions options;
    options.layout = *bim::ParseBuildingLayout(o.layout);  // CLI11 checked the name
    options.length_unit_m = o.unit == "mm" ? 0.001 : 1.0;
    options.seed = o.seed;
    options.furniture = !o.no_furniture;
    options.exterior_doors = o.exterior_doors;
    options.storeys = o.storeys;
    bim::WriteSampleBuilding(path, options);
    const bim::SampleLayout L = bim::SampleBuildingLayout(options);

    std::cout << "wrote        " << path.string() << " (" << std::fixed << std::setprecision(1)
              << double(fs::file_size(path)) / 1e3 << " kB), IFC4, lengths in "
              << (o.unit == "mm" ? "millimetres" : "metres") << ", seed " << o.seed << "\n";
    std::cout << "building     " << L.building_name << " (layout " << o.layout << "), "
              << L.footprint_m.x() << " x " << L.footprint_m.y() << " m, " << L.storeys.size()
              << (L.storeys.size() == 1 ? " storey" : " storeys") << "\n";
    std::cout << std::setprecision(2);
    for (size_t s = 0; s < L.storeys.size(); ++s) {
        std::ostringstream rooms;
        int count = 0;
        for (const bim::SampleRoom& r : L.rooms) {
            if (r.storey != int(s)) continue;
            rooms << (count++ ? ", " : "") << r.number << " " << r.name;
        }
        std::cout << "storey       " << L.storeys[s].name << " at " << L.storeys[s].elevation_m
                  << " m: " << count << " rooms (" << rooms.str() << ")\n";
    }
    size_t slab_openings = 0;
    for (const bim::SampleSlab& s : L.slabs) slab_openings += s.openings.size();
    std::cout << "elements     " << L.walls.size() << " IfcWall, " << L.doors.size() << " IfcDoor, "
              << L.windows.size() << " IfcWindow, " << L.columns.size() << " IfcColumn, "
              << L.slabs.size() << " IfcSlab, " << L.stairs.size()
              << " IfcStair (+ IfcStairFlight), " << L.railings.size() << " IfcRailing, "
              << L.furniture.size() << " IfcFurniture\n"
              << "             " << L.rooms.size() << " IfcSpace, "
              << L.doors.size() + L.windows.size() + slab_openings << " IfcOpeningElement\n";
    const Eigen::AlignedBox3d box = L.Bounds();
    std::cout << "extent       " << box.sizes().x() << " x " << box.sizes().y() << " x "
              << box.sizes().z() << " m (z " << box.min().z() << " to " << box.max().z() << " m)\n";
    return kExitOk;
}

}  // namespace

void AddBimSampleCommand(CLI::App& bim, int& exit_code) {
    CLI::App* cmd = bim.add_subcommand(
        "sample",
        "Write a built-in sample building (office, hall, symmetric or wing) as an IFC4 file");
    cmd->footer(
        "Layouts (host_tools/bim/README.md):\n"
        "  office     two storeys, 30 x 15 m, 3.2 m floor to floor: a corridor along x, offices,\n"
        "             a stair, a slanted wall (the default; the demo's building)\n"
        "  hall       three storeys, 24 x 20 m, 3.5 m floor to floor: a central hall with\n"
        "             columns on the ground floor, corridors along y above, a stair hall with\n"
        "             two flights; --exterior-doors adds the entrance in the south wall;\n"
        "             --storeys 2 to 8 makes it lower or taller (the upper plans and the\n"
        "             flights take turns)\n"
        "  symmetric  one storey, 20 x 12 m, the same under the mirror about both centre lines\n"
        "             (and a half turn): a rig in it cannot tell where it is up to the symmetry;\n"
        "             --exterior-doors adds the same entrance at both ends\n"
        "  wing       two storeys, 90 x 15 m, 3.2 m floor to floor: the office's plan along a\n"
        "             long corridor, 3.5-10 m rooms on both sides, a straight stair at its east\n"
        "             end; a walk along it keeps entering space it has not seen");
    auto o = std::make_shared<SampleOptions>();
    cmd->add_option("-o,--out", o->out, "the IFC file to write")->required();
    cmd->add_option("--layout", o->layout, "which building: office, hall, symmetric or wing")
        ->check(CLI::IsMember({"office", "hall", "symmetric", "wing"}))
        ->capture_default_str();
    cmd->add_option("--unit", o->unit, "length unit of the file: m or mm")
        ->check(CLI::IsMember({"m", "mm"}))
        ->capture_default_str();
    cmd->add_option("--seed", o->seed, "varies the furniture and the GlobalIds")
        ->capture_default_str();
    cmd->add_flag("--no-furniture", o->no_furniture, "leave the furniture out");
    cmd->add_flag("--exterior-doors", o->exterior_doors,
                  "doors to the outside on the ground floor (see the layouts)");
    cmd->add_option("--storeys", o->storeys,
                    "the hall's number of storeys, 2 to 8 (default: its three)")
        ->check(CLI::Range(2, 8));
    cmd->add_flag("--force", o->force, "overwrite an existing file");
    cmd->callback([o, &exit_code] { exit_code = Run([&] { return Sample(*o); }); });
}

}  // namespace bimslam::cli
