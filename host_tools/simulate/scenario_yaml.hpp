// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Scenario <-> YAML. The layout mirrors the structs (scenario.hpp): top-level keys model, storey,
// platform, path, speed, duration_s, sensor, network, noise, seed, edits; nested keys are the
// field names. host_tools/simulate/scenarios/go1_coverage.yaml is the commented reference.
//
// Reading is strict, since a misspelt key silently keeping its default would make a capture that
// differs from what its author meant: every unknown key, wrong type, wrong vector length and
// invalid value is an error naming the file, the line where yaml-cpp knows it, and the key's full
// path (e.g. "edits.boxes[0].size").
#pragma once

#include <filesystem>
#include <string>

#include "host_tools/simulate/scenario.hpp"

namespace bimslam::simulate {

// Reads a scenario file. Relative paths in it (model, sensor.metadata, edits.meshes[].file)
// are resolved against the file's folder. Throws common::FileError naming the file (and the line
// for syntax errors and misplaced keys).
Scenario LoadScenario(const std::filesystem::path& file);

// Parses scenario text: starts from DefaultScenario(platform) (`platform:` picks the defaults,
// Go1 without it), overlays the keys present, then validates. `name` is used in error messages
// (the file name); relative paths are resolved against `base_dir` (left relative when it is
// empty). Throws common::FileError with path() == name.
Scenario ParseScenario(const std::string& name, const std::string& text,
                       const std::filesystem::path& base_dir);

// Every field of the scenario (paths as they are, numbers in their shortest exact form), so that
// ParseScenario reads back an equal scenario: the record of what a capture was made from.
std::string ScenarioToYaml(const Scenario& scenario);

}  // namespace bimslam::simulate
