// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The platform's own body as the sensor sees it (issue 17, item 6: "the rig's own body in view"),
// as boxes in the platform's base frame (simulation::BodyTrajectory's base: the Go1's trunk
// centre, the handheld base at chest height, the vehicle's roof). The simulator casts it in the
// sensor frame (SimulatorOptions::rig), so it moves with the sensor exactly.
//
// Sizes, approximate: a Go1's trunk is 0.65 x 0.28 x 0.12 m with its legs 0.19 m forward and back
// and 0.13 m to the sides of its centre; an adult holding the rig at chest height stands 0.35 m
// behind it with forearms reaching forward to the handle; a small car's roof is 2.4 x 1.6 m with
// the body 0.6 to 1.3 m below it, 4.4 m long.
#pragma once

#include "algorithms/common/triangle_mesh.hpp"
#include "host_tools/simulate/scenario.hpp"

namespace bimslam::simulate {

common::TriangleMesh RigBody(Platform platform);

}  // namespace bimslam::simulate
