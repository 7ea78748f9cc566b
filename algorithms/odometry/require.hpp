// The one check every odometry and keyframe …Config::Validate() uses: a message naming the
// struct, the field and the value (DESIGN.md, "Conventions").
#pragma once

#include <string>

#include "algorithms/common/status.hpp"

namespace bimslam::odometry {

inline void Require(bool ok, const char* config, const char* field, double value,
                    const char* rule) {
    if (!ok) {
        throw common::Error(
            common::StatusCode::kInvalidArgument,
            std::string(config) + "." + field + " = " + std::to_string(value) + ": " + rule);
    }
}

}  // namespace bimslam::odometry
