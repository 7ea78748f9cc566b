// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A light index of an ISO 10303-21 (STEP) file's DATA section: where each entity instance is, its
// id, its type and its GlobalId, and where the section ends; enough to append entities that refer
// to existing ones (the updated IFC of `bimslam changes`) without re-serialising the model.
// Strings ('...' with '' escapes) and comments (/* ... */) are skipped, so a ';' or "ENDSEC" in a
// name does not cut an entity.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace bimslam::change_detection {

struct StepEntity {
    int id = 0;
    std::string type;       // upper case, e.g. "IFCBUILDINGSTOREY"
    std::string_view args;  // the text between the outer parentheses
    std::string global_id;  // the first argument when it is a string (IfcRoot's GlobalId)
};

class StepIndex {
public:
    // Keeps a view of `text`: it must outlive the index. Throws common::FileError naming `name`
    // when there is no DATA section or it is not closed by ENDSEC.
    StepIndex(const std::string& name, std::string_view text);

    int max_id() const { return max_id_; }
    // Offset of the ENDSEC that closes the DATA section (where entities are appended).
    size_t data_end() const { return data_end_; }
    // The file's line ending ("\r\n" when its first line ends so, else "\n").
    const std::string& newline() const { return newline_; }

    const std::vector<StepEntity>& entities() const { return entities_; }
    // The entity with this GlobalId, or nullptr.
    const StepEntity* FindGlobalId(const std::string& global_id) const;
    // The entities of a type (upper case), in file order.
    std::vector<const StepEntity*> OfType(std::string_view type) const;
    // The top-level comma-separated arguments of an entity (nested lists kept whole, trimmed).
    static std::vector<std::string_view> SplitArgs(std::string_view args);

private:
    int max_id_ = 0;
    size_t data_end_ = 0;
    std::string newline_ = "\n";
    std::vector<StepEntity> entities_;
    std::map<std::string, size_t, std::less<>> by_global_id_;
};

}  // namespace bimslam::change_detection
