// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The inputs of `bimslam map`, checked before any step runs (exit 2 naming the file): the model
// must be an IFC file (an ISO-10303-21 header whose FILE_SCHEMA names an IFC schema), and every
// recording an Ouster capture (a capture folder or x.pcap + x.json, io::ResolveCapture) whose
// metadata parses and whose pcap holds packets of that sensor (capture::OusterCapture).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "algorithms/io/capture_files.hpp"

namespace bimslam::mapping {

struct RecordingInput {
    std::filesystem::path path;  // as given
    std::string name;            // its folder's (or the pcap's stem), unique among the inputs
    io::CaptureFiles files;
    // A simulated capture's truth beside it (bimslam simulate); empty when absent.
    std::filesystem::path ground_truth;   // ground_truth.tum
    std::filesystem::path truth_changes;  // changes.json
};

// Throws common::FileError (kParseError / kNotFound) naming the file and what is wrong.
void CheckModelFile(const std::filesystem::path& model);
// Resolves and checks each recording; names are made unique ("name", "name_2", ...).
std::vector<RecordingInput> CheckRecordings(const std::vector<std::filesystem::path>& recordings);

}  // namespace bimslam::mapping
