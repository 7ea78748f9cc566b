// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam bim stairs: the building's walkable 3D graph (host_tools/bim/stairs.hpp): its floors,
// the flights that join them (each against what its file declares of it), and what cannot be
// walked.
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "host_tools/bim/building_graph.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/cli/command.hpp"

namespace bimslam::cli {
namespace {

struct StairsArgs {
    std::string model;
    std::string platform = "handheld";
    bool json = false;
};

// Each walking surface: its centre (x, y, z), area, depth and width.
nlohmann::json Levels(const bim::StairFlight& f) {
    nlohmann::json out = nlohmann::json::array();
    for (const bim::StairLevel& l : f.levels) {
        out.push_back({{"centre", {l.centre.x(), l.centre.y(), l.centre.z()}},
                       {"area_m2", l.area_m2},
                       {"depth_m", l.depth_m},
                       {"width_m", l.width_m}});
    }
    return out;
}

// What the file declares of the flight (null: nothing), its lengths as the file's unit reads them
// (lengths_in_feet: they agree only read in feet), and what of it the geometry contradicts.
nlohmann::json DeclaredJson(const bim::StairFlight& f) {
    const bim::DeclaredFlight& d = f.declared;
    const bim::DeclaredCheck check = bim::CheckDeclared(f);
    if (!check.declared) return nullptr;
    return {{"risers", d.risers},
            {"treads", d.treads},
            {"riser_height_m", d.riser_height_m},
            {"tread_length_m", d.tread_length_m},
            {"lengths_in_feet", check.in_feet},
            {"differs", check.differs}};
}

// "declared 16 risers, 15 treads, risers of 0.200 m, treads of 0.280 m: agrees" (or what
// differs), the lengths read in feet where they agree only so.
std::string DeclaredText(const bim::StairFlight& f) {
    const bim::DeclaredFlight& d = f.declared;
    const bim::DeclaredCheck check = bim::CheckDeclared(f);
    if (!check.declared) return "declared nothing (no IfcStairFlight attributes)";
    const double scale = check.in_feet ? bim::kFootM / d.length_unit_m : 1.0;
    std::string out = "declared";
    if (d.risers > 0) out += " " + std::to_string(d.risers) + " risers";
    if (d.treads > 0) out += ", " + std::to_string(d.treads) + " treads";
    if (d.riser_height_m > 0) out += ", risers of " + Fixed(d.riser_height_m * scale, 3) + " m";
    if (d.tread_length_m > 0) out += ", treads of " + Fixed(d.tread_length_m * scale, 3) + " m";
    if (check.in_feet) out += " (its lengths written in feet, not in the file's unit)";
    return out + (check.differs.empty() ? ": agrees" : ": DIFFERS (" + check.differs + ")");
}

nlohmann::json FlightJson(const bim::BimModel& m, const bim::StairFlight& f) {
    auto storey = [&](int s) { return s < 0 ? std::string() : m.storeys[size_t(s)].name; };
    return {{"name", f.name},
            {"global_ids", f.global_ids},
            {"ramp", f.ramp},
            {"lower", storey(f.lower)},
            {"upper", storey(f.upper)},
            {"levels", Levels(f)},
            {"risers", f.risers},
            {"rise_m", f.rise_m},
            {"run_m", f.run_m},
            {"width_m", f.width_m},
            {"pitch_deg", f.pitch_deg},
            {"length_m", f.Walkable() ? f.LengthM() : 0.0},
            {"entry", {f.entry.x(), f.entry.y()}},
            {"exit", {f.exit.x(), f.exit.y()}},
            {"entry_cell", {f.entry_cell.x(), f.entry_cell.y()}},
            {"exit_cell", {f.exit_cell.x(), f.exit_cell.y()}},
            {"walkable", f.Walkable()},
            {"problem", f.problem},
            {"declared", DeclaredJson(f)}};
}

void PrintText(const bim::BimModel& m, const bim::BuildingGraph& g) {
    std::cout << "floors   ";
    for (const int s : g.floors) {
        std::cout << "'" << m.storeys[size_t(s)].name << "' ("
                  << Fixed(m.storeys[size_t(s)].elevation_m, 2) << " m"
                  << (g.Reaches(s) ? "" : ", not reached") << ")  ";
    }
    std::cout << "\n";
    for (const bim::StairFlight& f : g.flights) {
        std::cout << "flight   " << f.name << ": ";
        if (f.lower >= 0 && f.upper >= 0) {
            std::cout << "'" << m.storeys[size_t(f.lower)].name << "' -> '"
                      << m.storeys[size_t(f.upper)].name << "', ";
        }
        std::cout << f.risers << " risers of " << Fixed(f.rise_m, 3) << " m, run "
                  << Fixed(f.run_m, 3) << " m, width " << Fixed(f.width_m, 2) << " m, "
                  << Fixed(f.pitch_deg, 1) << " deg";
        if (f.Walkable()) {
            std::cout << ", entry (" << Fixed(f.entry.x(), 2) << ", " << Fixed(f.entry.y(), 2)
                      << "), exit (" << Fixed(f.exit.x(), 2) << ", " << Fixed(f.exit.y(), 2) << ")";
        }
        std::cout << (f.Walkable() ? "" : "  NOT WALKABLE") << "\n";
        std::cout << "         " << DeclaredText(f) << "\n";
    }
    std::cout << "reached  " << g.reached.size() << " of " << g.floors.size() << " floors from '"
              << m.storeys[size_t(g.start)].name << "'\n";
}

int Stairs(const StairsArgs& a) {
    const bim::BimModel model = bim::LoadIfc(a.model);
    const bool go1 = a.platform == "go1";
    const bim::BuildingGraph g = bim::BuildBuildingGraph(
        model, bim::GridConfig{}, go1 ? bim::StairLimits::Go1() : bim::StairLimits{},
        go1 ? 0.3 : 0.35, bim::DefaultWalkStorey(model));
    if (a.json) {
        nlohmann::json j;
        j["model"] = a.model;
        j["platform"] = a.platform;
        j["start"] = model.storeys[size_t(g.start)].name;
        for (const int s : g.floors) {
            j["floors"].push_back({{"name", model.storeys[size_t(s)].name},
                                   {"elevation_m", model.storeys[size_t(s)].elevation_m},
                                   {"reached", g.Reaches(s)}});
        }
        j["flights"] = nlohmann::json::array();
        for (const bim::StairFlight& f : g.flights) j["flights"].push_back(FlightJson(model, f));
        j["problems"] = g.problems;
        j["all_reached"] = g.AllReached();
        std::cout << j.dump(2) << "\n";
    } else {
        PrintText(model, g);
    }
    for (const std::string& p : g.problems) std::cerr << a.model << ": " << p << "\n";
    return g.AllReached() ? kExitOk : kExitBadInput;
}

}  // namespace

void AddBimStairsCommand(CLI::App& bim, int& exit_code) {
    auto a = std::make_shared<StairsArgs>();
    auto* cmd = bim.add_subcommand(
        "stairs",
        "The building's walkable 3D graph: its floors, the stair and ramp flights that join them "
        "(rise, run, width, entry and exit), each against what the file declares of it "
        "(IfcStairFlight's risers, treads, riser height and tread length), and which floors a walk "
        "reaches. Exit 2 when a floor cannot be reached (the reason is printed, naming the "
        "storeys)");
    cmd->add_option("MODEL", a->model, "IFC model (IFC2X3 or IFC4, any length unit)")->required();
    cmd->add_option("--platform", a->platform, "whose limits: go1 or handheld")
        ->check(CLI::IsMember({"go1", "handheld"}))
        ->capture_default_str();
    cmd->add_flag("--json", a->json, "machine-readable output");
    cmd->callback([a, &exit_code] { exit_code = Run([&] { return Stairs(*a); }); });
}

}  // namespace bimslam::cli
