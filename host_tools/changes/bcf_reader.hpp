// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Reading BCF-XML files (versions 2.1 and 3.0), ours or another tool's: the project, each topic
// with its words, every viewpoint (camera, selected, coloured and visibility components, the
// snapshot's bytes) and its comments. `bimslam bcf info` prints them; the tests read back what
// bcf_writer.hpp writes (the second reader the BCF tests need for 3.0, which bcf-js cannot read)
// and buildingSMART's own examples (../shared/specs/bcf/examples/).
//
// Where the versions differ (bcf_writer.hpp lists it): 2.1's Viewpoints and Comment elements
// stand beside Topic, 3.0's inside it (Topic/Viewpoints/ViewPoint, Topic/Comments/Comment); 2.1
// repeats Labels, 3.0 holds Label elements; 3.0's Coloring/Color holds Components/Component;
// 3.0's Header holds Files/File. Element names are matched without a namespace (the schemas
// have no target namespace).
//
// The input is somebody else's file: nothing is fetched (no network, no external entities), a
// zip entry over kMaxBcfEntryBytes is refused before it is inflated, and every fault is a
// common::FileError naming the file, the zip entry and, for XML, the line.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "host_tools/changes/bcf_writer.hpp"

namespace bimslam::change_detection {

// An entry larger than this (inflated) is refused: a snapshot or an XML file of a BCF is a few
// megabytes at most, and a zip bomb must not take the host's memory.
inline constexpr size_t kMaxBcfEntryBytes = size_t{64} << 20;

struct BcfComment {
    std::string guid, date, author, text;
    std::string viewpoint_guid;  // the viewpoint it refers to; empty: none
};

struct BcfReadTopic {
    // Its words and, in `topic.viewpoint`, the first of `viewpoints` (the lowest Index); a topic
    // without viewpoints has an empty one.
    BcfTopic topic;
    std::vector<BcfViewpoint> viewpoints;  // by their Index, then as the markup lists them
    std::vector<BcfComment> comments;
    std::string modified_date, due_date, assigned_to;
};

struct BcfFile {
    BcfVersion version = BcfVersion::k2_1;
    BcfProject project;               // empty id and name when project.bcfp is absent
    std::vector<BcfReadTopic> topics;  // in the zip's order of their folders
};

// Throws common::FileError (`name` as the path): not a zip, no bcf.version, a version other
// than 2.1 and 3.0, XML that does not parse (with its entry and line), a topic without a Guid, a
// markup naming a viewpoint or snapshot file the zip lacks, an entry over kMaxBcfEntryBytes.
BcfFile ReadBcf(const std::filesystem::path& path);
BcfFile ReadBcfBytes(const std::string& name, std::string_view bytes);

}  // namespace bimslam::change_detection
