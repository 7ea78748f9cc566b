// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/changes/survey_datum.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "host_tools/changes/bim_change_model.hpp"

namespace bimslam::change_detection {
namespace {

std::string Trim(const std::string& s) {
    const size_t a = s.find_first_not_of(" \t\r");
    if (a == std::string::npos) return "";
    return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

}  // namespace

void CheckSurveyDatumOption(const std::filesystem::path& file, bool refinement_enabled) {
    if (!refinement_enabled) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "--datum holds the refinement's gauge; it has no use with --no-refine");
    }
    if (!std::filesystem::is_regular_file(file)) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            file.string() + ": no such file (--datum)");
    }
}

std::vector<changes::SurveyedElement> ReadSurveyDatum(const std::filesystem::path& file,
                                                      const bim::BimModel& model) {
    const std::string text = io::ReadFileToString(file);  // throws naming the file
    std::map<std::string, uint32_t> by_id;
    for (size_t e = 0; e < model.elements.size(); ++e) {
        by_id.emplace(model.elements[e].global_id, uint32_t(e));
    }
    std::vector<changes::SurveyedElement> out;
    std::map<uint32_t, size_t> listed;  // element -> line
    std::istringstream in(text);
    size_t number = 0;
    for (std::string line; std::getline(in, line);) {
        ++number;
        const std::string where = file.string() + ":" + std::to_string(number) + ": ";
        auto fail = [&](const std::string& what) {
            throw common::Error(common::StatusCode::kInvalidArgument, where + what);
        };
        line = Trim(line.substr(0, line.find('#')));  // IFC GlobalIds never hold '#'
        if (line.empty() || (out.empty() && line.starts_with("global_id"))) {
            continue;
        }
        std::vector<std::string> fields;
        std::istringstream cells(line);
        for (std::string f; std::getline(cells, f, ',');) fields.push_back(Trim(f));
        if (fields.size() != 1 && fields.size() != 4) {
            fail("expected GlobalId or GlobalId,dx,dy,dz (metres), found " +
                 std::to_string(fields.size()) + " fields");
        }
        const auto it = by_id.find(fields[0]);
        if (it == by_id.end()) fail("the model has no element with GlobalId '" + fields[0] + "'");
        const bim::BimElement& el = model.elements[it->second];
        if (!Physical(el) || el.triangle_count == 0) {
            fail(fields[0] + " is " + el.ifc_class +
                 " without geometry to survey (not a physical element with a shape)");
        }
        if (const auto [at, fresh] = listed.emplace(it->second, number); !fresh) {
            fail(fields[0] + " is listed twice (first on line " + std::to_string(at->second) + ")");
        }
        changes::SurveyedElement d;
        d.element = it->second;
        for (size_t i = 1; i < fields.size(); ++i) {
            const char* begin = fields[i].c_str();
            char* end = nullptr;
            errno = 0;
            const double v = std::strtod(begin, &end);
            if (fields[i].empty() || *end != '\0' || errno != 0 || !std::isfinite(v)) {
                fail("'" + fields[i] + "' is not a number (offset in metres)");
            }
            d.offset[int(i) - 1] = v;
        }
        if (d.offset.norm() >= 1.0) {
            fail("an offset of " + std::to_string(d.offset.norm()) +
                 " m: a datum is an element built a little off, not one that moved");
        }
        out.push_back(d);
    }
    if (out.empty()) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            file.string() +
                                ": no surveyed element (expected lines "
                                "GlobalId[,dx,dy,dz])");
    }
    return out;
}

}  // namespace bimslam::change_detection
