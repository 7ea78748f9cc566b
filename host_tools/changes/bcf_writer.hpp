// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// BCF-XML files (buildingSMART's BIM Collaboration Format, versions 2.1 and 3.0): topics, each
// with one viewpoint (perspective camera, selected and coloured components by IFC GlobalId) and
// its PNG snapshot, in a zip. XML by libxml2's xmlTextWriter, the zip by libzip.
//
// Layout (BCF-XML 2.1 and 3.0 READMEs; schemas in ../shared/specs/bcf/<version>/):
//   bcf.version                 Version VersionId="2.1" | "3.0"           (version.xsd)
//   project.bcfp                ProjectExtension (2.1) | ProjectInfo (3.0) (project.xsd)
//   extensions.xml              3.0 only: the topic types, statuses, priorities, labels used
//   <topic guid>/markup.bcf     Markup: Header/File, Topic, Viewpoints     (markup.xsd)
//   <topic guid>/viewpoint.bcfv VisualizationInfo                          (visinfo.xsd)
//   <topic guid>/snapshot.png
// Where the two versions differ: 2.1 puts Viewpoints (and Comment) beside Topic, 3.0 inside it
// as Topic/Viewpoints/ViewPoint; 2.1's Labels repeat, 3.0's hold Label elements; 3.0's
// PerspectiveCamera has AspectRatio, 2.1's FieldOfView is limited to 45..60 degrees; 2.1's
// Components needs Visibility, 3.0's Coloring/Color holds Components/Component; 3.0's GUIDs are
// lower case. Times are xs:dateTime in UTC ("2026-12-02T11:30:00Z").
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace bimslam::change_detection {

enum class BcfVersion { k2_1, k3_0 };
// "2.1" / "3.0".
const char* ToString(BcfVersion version);
// Throws common::Error (kInvalidArgument) for anything but "2.1" and "3.0".
BcfVersion ParseBcfVersion(const std::string& text);

// A viewpoint's camera: bimslam writes perspective ones; other tools' files may hold an
// orthogonal one, or none (a viewpoint of components only).
enum class BcfCamera { kNone, kPerspective, kOrthogonal };

struct BcfViewpoint {
    std::string guid;
    BcfCamera camera = BcfCamera::kPerspective;
    Eigen::Vector3d eye = Eigen::Vector3d::Zero();  // the model's coordinates, metres
    Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
    Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
    double fov_deg = 60;  // vertical (perspective)
    double view_to_world_scale = 0;  // the view's height in metres (orthogonal)
    double aspect = 4.0 / 3.0;
    std::vector<std::string> selected;  // IFC GlobalIds
    // Every component shown (true) but the exceptions, or none shown but the exceptions.
    bool default_visibility = true;
    std::vector<std::string> visibility_exceptions;
    // "RRGGBB" -> GlobalIds drawn in that colour.
    std::vector<std::pair<std::string, std::vector<std::string>>> colors;
    std::string snapshot_png;  // the PNG's bytes; empty: none
};

struct BcfTopic {
    std::string guid;
    std::string type, status, priority, title, description;
    std::vector<std::string> labels;
    std::string creation_date;  // xs:dateTime (common::FormatUtcTime)
    std::string author;
    int index = 0;
    std::string reference_file;  // the IFC file the topic is about (Header/File/Filename)
    BcfViewpoint viewpoint;
};

struct BcfProject {
    std::string id;  // a GUID
    std::string name;
    // 3.0's extensions.xml: every value the topics may take (a merged file's topics included).
    std::vector<std::string> topic_types, topic_statuses, priorities, labels, users;
};

// A UUID made from a name (SHA-256 of it; version 8, RFC 9562's custom layout), lower case: the
// same name gives the same GUID, so a run again gives the same topics.
std::string NameGuid(const std::string& name);

// The zip's bytes. Entries carry `unix_ns` as their time, so the same topics give the same
// bytes. Throws common::Error (kInternal) when libxml2 or libzip fails, with what they said.
std::string BcfZip(const BcfProject& project, const std::vector<BcfTopic>& topics,
                   BcfVersion version, int64_t unix_ns);

// The topics of several BCF zips of one version in one (the first's bcf.version, project and
// extensions; every topic folder of each): a project's visit of several recordings. Throws
// common::FileError naming a file that cannot be read or is not a zip.
std::string MergeBcf(const std::vector<std::filesystem::path>& files, int64_t unix_ns);

}  // namespace bimslam::change_detection
