// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// `bimslam changes --datum FILE`: elements surveyed as built, which fix the pose refinement's gauge
// (algorithms/changes/pose_refinement.hpp, "Gauge"). Without them the refinement can only take the
// building to stand, on average, where the model says, and every wall's measured deviation then
// carries the mean offset of the walls seen along its normal (algorithms/changes/README.md).
//
// The file: one element per line, `GlobalId[,dx,dy,dz]`, the offset of the element as built from
// where the model has it, in metres along the model's axes (a total station's survey of a few
// elements, as Scan-vs-BIM work registers on control). A GlobalId alone: surveyed where the model
// says. '#' starts a comment; blank lines and a first line starting with "global_id" (a header)
// are skipped.
#pragma once

#include <filesystem>
#include <vector>

#include "algorithms/changes/pose_refinement.hpp"
#include "host_tools/bim/bim_model.hpp"

namespace bimslam::change_detection {

// What a `--datum FILE` option is checked for before any model is read (`bimslam changes` and
// `bimslam map`): the refinement it holds must be on, and the file must exist. Throws common::Error
// (kInvalidArgument).
void CheckSurveyDatumOption(const std::filesystem::path& file, bool refinement_enabled);

// Throws common::Error (kInvalidArgument) naming the file and line: unreadable, no element, a
// field that is not a number, a wrong number of fields, a GlobalId the model does not have or
// that is not a physical element with geometry, one listed twice, an offset of 1 m or more.
std::vector<changes::SurveyedElement> ReadSurveyDatum(const std::filesystem::path& file,
                                                      const bim::BimModel& model);

}  // namespace bimslam::change_detection
