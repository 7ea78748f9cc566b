// The report's deviation views (issue 34 item 3): each compared element's measured deviation and
// its verdict against the QA tolerance (elements.csv, `bimslam changes --tolerance`), which the
// plans and the 3D view colour elements by.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "host_tools/bim/bim_model.hpp"

namespace bimslam::report {

// The tolerance verdicts of elements.csv, as the page codes them.
enum DeviationCode : int { kWithin = 0, kBeyond = 1, kNotObserved = 2 };

// The elements of the visit's recordings' change folders (each with changes.json and
// elements.csv): {tolerance_m, elements: [[GlobalId, code, offset_m], ...]}. By GlobalId: the
// changes step reads the model with its spaces, the report without, so indices differ. An
// element several recordings compared takes the verdict of the one that measured it (within or
// beyond before not observed), then of the one with the most support points. Null when no folder
// has an elements.csv with tolerance verdicts (an output of an older bimslam).
nlohmann::json ElementDeviations(const std::vector<std::filesystem::path>& change_dirs);

}  // namespace bimslam::report
