// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A storey's plan in text, from the rig's map package (algorithms/localization/rig_map.hpp), with
// the rig's walk and pose on it: what `bimslam live` draws in the terminal. The walls are the
// package's finest surfels that stand upright between 0.3 and 2 m above the storey's floor (the
// band a sensor on a Go1 or in a hand sees), so the plan needs nothing but the package.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/localization/rig_map.hpp"

namespace bimslam::live {

// What the frame shows: the relocaliser's state and, when localised, the rig's position and
// heading in the model and the storey it is on; the walk so far (positions in the model).
struct LiveState {
    std::string state = "searching";  // bim_pose_t's STATE_* as text
    int consistent_loops = 0, hypotheses = 0;
    std::optional<Eigen::Vector3d> position;  // localised only
    double yaw = 0;                           // rad, about the model's z
    int storey = -1;                          // into the package's storeys; -1: unknown
    std::string space;                        // the IfcSpace it stands in; "": none
    std::vector<Eigen::Vector3d> walk;
    double t_s = 0;  // sensor time of the last message, s
};

class PlanView {
public:
    explicit PlanView(const localization::RigMap& map);

    // `width` columns of characters (two per metre's row, as terminal cells are about twice as
    // tall as wide); a header line with the state, the storey and the position, then the plan:
    // '#' a wall, '.' the walk, the rig as an arrow (> ^ < v) by its heading.
    std::string Render(const LiveState& state, int width = 100) const;

    // A storey's walls as points in the model's x-y (the surfels' centroids) and their extent.
    struct Plan {
        Eigen::Vector2d min = Eigen::Vector2d::Zero(), max = Eigen::Vector2d::Zero();
        std::vector<Eigen::Vector2d> walls;
    };
    // One per storey of the package, in its order.
    const std::vector<Plan>& plans() const { return plans_; }
    const localization::RigMap& map() const { return map_; }

private:
    const localization::RigMap& map_;
    std::vector<Plan> plans_;  // per storey
};

}  // namespace bimslam::live
