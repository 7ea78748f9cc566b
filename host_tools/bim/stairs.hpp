// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Stairs and ramps read from the model's geometry (the walkable 3D graph that joins the storeys
// by them is building_graph.hpp).
//
// A stair is found from its geometry, whatever the exporter wrote about it: the elements of class
// IfcStair, IfcStairFlight, IfcRamp and IfcRampFlight, and the small slabs between floors that
// touch them (landings: Office_A writes them as IfcSlab parts of the IfcStair), whose boxes touch
// form one stair. Its walking surfaces are the horizontal faces (|n_z| > 0.9, so ramps up to 25
// degrees too) with nothing of the same stair within 0.5 m above them and not at a storey's
// floor: tops of treads and landings, never undersides, whichever way an exporter orients its
// faces. Sampled on a 5 cm grid, they fall into levels by height (a ramp into 5 cm bands; slivers
// under 0.03 m2 or 40 % of the median level, such as a newel post's top, are dropped); the centre
// of each level, lowest first, is the walking line. Its bottom is joined to the storey whose floor
// lies up to 1.5 rises below its lowest level, its top to the one up to 1.5 rises above its
// highest (exporters' first and last risers differ from the rest: FZK-Haus's last is 5 cm).
#pragma once

#include <Eigen/Core>
#include <string>
#include <string_view>
#include <vector>

#include "host_tools/bim/bim_model.hpp"
#include "host_tools/bim/occupancy_grid.hpp"

namespace bimslam::bim {

// What a platform climbs. The defaults are a person's (who takes FZK-Haus's spiral stair, 48
// degrees at its walking line); a Go1 takes lower risers and flatter flights (StairLimits::Go1).
struct StairLimits {
    double max_riser_m = 0.25;
    double max_pitch_deg = 50.0;  // atan(rise / run) on the walking line
    double min_width_m = 0.7;     // the clear width of a tread (twice the walk's clearance)
    // How far from the first and last riser the walk stands before and after the flight.
    double standing_m = 0.5;

    static StairLimits Go1();  // risers up to 0.21 m, 40 degrees, 0.6 m wide
    void Validate() const;     // throws common::Error naming the field and value
};

// A walking surface of a stair: a tread, a landing, or a 5 cm band of a ramp.
struct StairLevel {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // centroid of its top surface
    double area_m2 = 0;
    double depth_m = 0;    // its extent along the walking line there
    bool landing = false;  // more than twice the median level's area
    double width_m = 0;    // its extent across the walking line there
};

struct StairFlight {
    std::string name;                     // "IfcStair 'Stair' (GlobalId)": its first element
    std::vector<std::string> global_ids;  // every element it is made of
    bool ramp = false;
    std::vector<StairLevel> levels;  // the walking line, bottom first
    int lower = -1, upper = -1;      // storeys it joins (indices into BimModel::storeys)
    double lower_z = 0, upper_z = 0;
    int risers = 0;  // levels + 1
    // Medians over the treads (landings left out): the rise between levels, the run between their
    // centres in plan, the width across the line; pitch = atan(rise / run).
    double rise_m = 0, run_m = 0, width_m = 0, pitch_deg = 0;
    // Where the walk stands on the lower floor before the first riser, and on the upper floor after
    // the last (model x y), and their grid cells.
    Eigen::Vector2d entry = Eigen::Vector2d::Zero(), exit = Eigen::Vector2d::Zero();
    Eigen::Vector2i entry_cell{-1, -1}, exit_cell{-1, -1};
    std::string problem;  // why it cannot be walked; empty when it can
    // What the file declares of it, over its IfcStairFlight elements: their risers and treads
    // summed, the median of their riser heights and tread lengths (all 0: nothing declared).
    DeclaredFlight declared;

    bool Walkable() const { return problem.empty(); }
    // The walked line from entry to exit, bottom to top: (x, y, floor z) with each riser as two
    // points 1 mm apart in plan (the floor steps up there).
    std::vector<Eigen::Vector3d> Line() const;
    double LengthM() const;  // of Line() in plan
    // Up the flight in plan at its foot and at its head (unit; +x for a flight of one level).
    Eigen::Vector2d UpAtFoot() const;
    Eigen::Vector2d UpAtHead() const;
};

// The flights of every stair and ramp in the model, not yet checked against limits or grids
// (problem set only where the geometry itself says no: no walking surface, ends on no floor).
std::vector<StairFlight> FindStairFlights(const BimModel& model);

// Says in f.problem when the flight is too steep or too narrow for the limits (a flight with a
// problem already keeps it).
void CheckStairLimits(const StairLimits& limits, StairFlight& f);

// The flight found from the geometry against what its file declares (an outside yardstick: the
// authoring tool's own numbers). Counts must agree to the one: the risers climbed (a flight's
// NumberOfRisers counts the riser up onto the floor above, as Revit writes it: Duplex_A's 16
// risers, 15 treads; the sample buildings too) and the treads, landings apart. Lengths: the riser
// height within kDeclaredRiseToleranceM, the tread length within kDeclaredRunToleranceM (the run
// is measured between treads' centres, which a nosing moves). Revit's exporters have written
// lengths in Revit's internal feet into files whose unit is the metre (Autodesk/revit-ifc#552;
// Duplex_A and Office_A: risers of 0.636 and 0.583 "m"): lengths that agree only read in feet
// agree, and in_feet says so.
inline constexpr double kDeclaredRiseToleranceM = 0.005;
inline constexpr double kDeclaredRunToleranceM = 0.02;
inline constexpr double kFootM = 0.3048;
struct DeclaredCheck {
    bool declared = false;  // the file declares anything of the flight
    bool in_feet = false;   // its lengths agree read in feet, not in the file's unit
    std::string differs;    // what contradicts the geometry, e.g. "23 risers in its geometry, 24
                            // declared"; "" when nothing does
};
DeclaredCheck CheckDeclared(const StairFlight& f);

// IfcStair, IfcStairFlight, IfcRamp or IfcRampFlight.
bool IsStairOrRampClass(std::string_view ifc_class);

}  // namespace bimslam::bim
