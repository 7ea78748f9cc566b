// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A `bimslam map` project (issue 33, item 1): the output folder keeps the model, its reference and
// every visit of the building. OUT/project.json holds the model (path and SHA-256) and the
// visits in date order, each with its label, date-time and recordings; each visit's odometry,
// anchoring and changes are in OUT/visits/<label>/ with their stamps, so a later run that adds
// recordings does not process the earlier visits again.
//
// The rules (README.md of this folder, "Visits"):
// - A recording's date-time is the capture's own when capture.json has one (`start_ns`, as
//   `bimslam simulate` writes it), else its first packet's capture time (the pcap record's, or the
//   bag message's).
// - A recording is the same recording when its packets file has the same size, the same first
//   packet time and the same first MiB (SHA-256): a copy or a move is recognised, and gets its
//   new path; it is never added twice.
// - A new recording joins the visit of its calendar day (UTC), labelled YYYY-MM-DD, made when
//   there is none; `--visit LABEL` puts the run's new recordings in the visit LABEL instead (a
//   named visit is never joined by date). Visits are ordered by their first recording's time.
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "host_tools/anchor/anchor_session.hpp"
#include "host_tools/mapping/map_inputs.hpp"

namespace bimslam::mapping {

struct ProjectRecording {
    std::string name;            // unique in the project: its folders in the visit
    std::filesystem::path path;  // absolute, as given last
    int64_t start_ns = 0;        // UNIX epoch
    std::string start_from;      // "capture.json" or "first packet"
    nlohmann::json identity;     // {size, first_packet_ns, head_sha256}
    // Where its walk starts, when the user said so (`--near`, anchor/anchor_session.hpp): kept
    // in project.json, so a later run anchors it with the same hint.
    std::optional<anchor::StartHint> start;
};

struct Visit {
    std::string label;                         // its folder in OUT/visits/
    bool named = false;                        // given by --visit (else its UTC day)
    std::vector<ProjectRecording> recordings;  // by start
    int64_t start_ns() const { return recordings.front().start_ns; }
};

struct Project {
    std::filesystem::path model;  // absolute
    std::string model_sha256;
    std::vector<Visit> visits;  // by start
};

// OUT/project.json; true when it exists. Throws common::FileError naming it when it is damaged.
bool LoadProject(const std::filesystem::path& out, Project* project);
void SaveProject(const std::filesystem::path& out, const Project& project);  // atomic

// A recording's date-time and identity (reads its first packet and first MiB).
ProjectRecording DescribeRecording(const RecordingInput& input);

// Adds the recordings not in the project yet (see the rules above; each input's name becomes its
// name in the project). A recording already there keeps its visit and name, takes the path given
// now, and is noted in `notes` when it was given under another path or with `adding` (`--add`:
// "already in visit L, not added again"); one that replaced a recording at its path (another
// identity) drops that one, with a note.
// `start` given: every one of `inputs` gets it, the ones already there too (the user says it
// anew).
void AddRecordings(Project& project, std::vector<RecordingInput>& inputs,
                   const std::string& visit_label, bool adding,
                   const std::optional<anchor::StartHint>& start, std::vector<std::string>* notes);

// Throws common::Error (kInvalidArgument) for a --visit label that cannot be a folder name.
void CheckVisitLabel(const std::string& label);

// Writes `text` to `file` (atomically) unless it holds it already: a run with nothing new leaves
// every file of OUT as it was, modification times too.
void WriteIfChanged(const std::filesystem::path& file, const std::string& text);

// OUT/visits/<label>.
std::filesystem::path VisitDir(const std::filesystem::path& out, const std::string& label);

// The project in `out` with this run's recordings in it (checked, not written yet: exit-2
// material is thrown before any step), and every visit's recordings resolved, in the project's
// order. `model` empty: the project's (`--add`), which must exist. Every recording of the project
// is checked (CheckRecordings) at its last path.
struct ProjectInputs {
    Project project;
    std::vector<std::vector<RecordingInput>> visits;  // as project.visits
    std::vector<std::string> notes;                   // AddRecordings', and a model that changed
};
ProjectInputs OpenProject(const std::filesystem::path& out, const std::filesystem::path& model,
                          const std::vector<std::filesystem::path>& recordings,
                          const std::string& visit, bool adding,
                          const std::optional<anchor::StartHint>& start = std::nullopt);

// Throws common::FileError (kDataLoss) naming the visit's folder when a step's stamp there says
// it was made but one of its files is missing or unreadable (what is wrong, and how to make the
// visit again). Reads only: nothing is changed.
void CheckVisitFolder(const std::filesystem::path& out, const Visit& visit);

}  // namespace bimslam::mapping
