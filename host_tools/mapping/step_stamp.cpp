// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/mapping/step_stamp.hpp"

#include <chrono>
#include <system_error>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/sha256.hpp"

namespace bimslam::mapping {
namespace fs = std::filesystem;

StepStamp::StepStamp(std::string step) {
    json_ = {{"format", "bimslam-map-stamp"},
             {"version", 1},
             {"step", std::move(step)},
             {"inputs", nlohmann::json::object()},
             {"upstream", nlohmann::json::object()},
             {"parameters", nlohmann::json::object()}};
}

void StepStamp::AddFileContent(const std::string& key, const fs::path& file) {
    // By content only: the same model copied or touched is the same model.
    json_["inputs"][key] = {{"sha256", io::Sha256File(file)}};
}

void StepStamp::AddFileTime(const std::string& key, const fs::path& file) {
    std::error_code ec;
    const auto size = fs::file_size(file, ec);
    // Not the path: a project moved with its recordings (or copied with their times, `cp -a`)
    // is the same project, and its steps are not done again. Which file is which the project
    // knows by the recording's identity (map_project.hpp); a file of the same size and time to
    // the nanosecond that is another recording is not a case worth hashing gigabytes for.
    nlohmann::json j = nlohmann::json::object();
    if (ec) {
        j["missing"] = true;
    } else {
        j["size"] = size;
        j["mtime_ns"] = fs::last_write_time(file, ec).time_since_epoch().count();
    }
    json_["inputs"][key] = j;
}

void StepStamp::AddUpstream(const StepStamp& upstream) {
    json_["upstream"][upstream.json_["step"].get<std::string>()] = upstream.Digest();
}

void StepStamp::AddParameter(const std::string& key, nlohmann::json value) {
    json_["parameters"][key] = std::move(value);
}

std::string StepStamp::Digest() const { return io::Sha256Hex(json_.dump()); }

bool StepStamp::Matches(const fs::path& file) {
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) return false;
    try {
        nlohmann::json stored = nlohmann::json::parse(io::ReadFileToString(file));
        if (!stored.is_object() || !stored.contains("made")) return false;
        const nlohmann::json made = stored["made"];
        stored.erase("made");
        nlohmann::json mine = json_;
        mine.erase("made");
        if (stored != mine) return false;
        json_["made"] = made;
        return true;
    } catch (const std::exception&) {
        return false;  // unreadable or not JSON: the step runs again and rewrites it
    }
}

void StepStamp::MarkMade() {
    json_["made"] = std::chrono::system_clock::now().time_since_epoch().count();
}

void StepStamp::Write(const fs::path& file) const {
    io::WriteFileAtomic(file, json_.dump(2) + "\n");
}

}  // namespace bimslam::mapping
