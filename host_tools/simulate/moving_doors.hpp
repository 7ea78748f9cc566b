// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Doors that swing while a capture runs (scenario edits.moving_doors): issue 17's "moving doors".
//
// The BIM's doors are left out of the static world (open: the walk passes through them). A moving
// door is a leaf, a 4 cm box of the door's width and height, turning about a vertical hinge at
// one end of the opening: closed (angle 0) it fills the opening, open it stands at right angles
// to the wall on the side the door swings to. Like people, the leaves are rebuilt every scan
// into the overlay scene (simulation::SimulatorOptions::overlay), at their angle at the scan's
// middle; their triangle id is the door's BIM element index, so a door's returns name the door.
// The walk is planned with the doors open and ignores the leaves, so a leaf is kept clear of the
// walker: near the walker it turns, from where its swing would put it, to the nearest angle that
// leaves kWalkerClearanceM between the leaf and the sensor (the walker pushes it open or it is
// held), as no leaf can sweep through a real walker. Elsewhere the doors swing.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "algorithms/common/triangle_mesh.hpp"
#include "host_tools/bim/bim_model.hpp"
#include "host_tools/simulate/scenario.hpp"

namespace bimslam::simulate {

struct MovingDoor {
    std::string global_id;
    uint32_t element = 0;                               // index into BimModel::elements
    Eigen::Vector2d hinge = Eigen::Vector2d::Zero();    // the vertical axis it turns about
    Eigen::Vector2d closed = Eigen::Vector2d::UnitX();  // unit, hinge -> other jamb
    Eigen::Vector2d swing = Eigen::Vector2d::UnitY();   // unit, the side it opens to
    double width_m = 1.0, height_m = 2.0, floor_z = 0.0;
    double period_s = 8.0, max_angle_deg = 90.0;
    double phase = 0.0;  // of its cycle, [0, 1)

    // max_angle (1 - cos(2 pi (t / period + phase))) / 2: smooth at both ends of the swing.
    double AngleDeg(double t) const;
};

// The doors edits.moving_doors names (by GlobalId or class; removed elements are skipped). The
// opening is read from the door's geometry: its topmost vertices (the frame's head, within 5 mm
// of its top) span the opening, their thinnest horizontal direction is the wall's normal; the
// hinge is at one end of that span, and the leaf opens to the side where the rest of the door's
// geometry lies (its leaves as modelled, open), else to the normal's side. Door k's phase is
// k times the golden ratio's fraction, so doors do not swing in step. Throws common::Error naming
// the edit when a GlobalId or class matches nothing.
std::vector<MovingDoor> FindMovingDoors(const bim::BimModel& model, const MovingDoorsSpec& spec,
                                        const std::vector<uint8_t>& removed);

// The room a leaf leaves the walker (in plan, from the sensor): a person's half shoulder width
// and a margin; the Go1 is narrower (0.28 m). A walker in a 1 m doorway is 0.5 m from its jamb.
inline constexpr double kWalkerClearanceM = 0.45;

// The leaf's angle at time t with the walker at (x, y): AngleDeg(t), or the angle nearest to it
// within [0, max_angle] whose leaf is kWalkerClearanceM from the walker (the clearest one when
// none is).
double LeafAngleDeg(const MovingDoor& door, double t, const Eigen::Vector2d& walker_xy);

// Appends each door's leaf at time t (seconds) to `mesh`, with the door's element index as id, at
// LeafAngleDeg.
void AppendDoorLeaves(const std::vector<MovingDoor>& doors, double t,
                      const Eigen::Vector2d& walker_xy, common::TriangleMesh* mesh,
                      std::vector<uint32_t>* ids);

}  // namespace bimslam::simulate
