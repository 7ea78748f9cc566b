// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// What a step of `bimslam map` was made from, so that a re-run can skip it: its inputs' identity
// (the model by SHA-256, recordings by size and modification time: hashing gigabytes of pcap on
// every run would cost more than some steps), the stamps of the steps it read, and its parameters.
// A step is up to date when its stamp file holds exactly the stamp a run would write now, but for
// the program that made it (StepStamp::Program, which the stamp names: said, not re-run).
//
// A stamp is written after its step's files, and removed before the step starts: a step that
// failed or was interrupted leaves no stamp, so the next run does it again.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace bimslam::mapping {

class StepStamp {
public:
    explicit StepStamp(std::string step);

    // A file identified by content (SHA-256).
    void AddFileContent(const std::string& key, const std::filesystem::path& file);
    // A file identified by size and modification time (nanoseconds), wherever it is; a missing
    // file is noted as missing (its appearance changes the stamp).
    void AddFileTime(const std::string& key, const std::filesystem::path& file);
    // The stamp of a step this one read: a change there changes this one.
    void AddUpstream(const StepStamp& upstream);
    void AddParameter(const std::string& key, nlohmann::json value);

    const nlohmann::json& json() const { return json_; }
    // SHA-256 of the stamp's text: what downstream stamps hold.
    std::string Digest() const;

    // True when `file` holds this stamp (its "made" token and program aside). A missing or
    // unreadable file is not up to date. When it matches, this stamp takes the file's token and
    // program.
    bool Matches(const std::filesystem::path& file);
    // The program that made the step: this one, unless a stamp Matches kept says another build
    // made it. Kept, not made again: a new build need not re-run a project's earlier visits (their
    // cost, their history), but `bimslam map` says which steps another build made (--force).
    bool MadeByThisProgram() const { return json_.value("program", "") == Program(); }
    // This program's identity: "build-id <hex>" (its GNU build ID), else "sha256 <hex>" of the
    // executable.
    static const std::string& Program();
    // A new token: the step ran now. Downstream stamps hold it through Digest(), so a step that
    // ran again (its stamp deleted, or it failed before) makes the steps after it run again too,
    // even when its inputs are the same (the odometry's results depend on the machine's load).
    void MarkMade();
    void Write(const std::filesystem::path& file) const;  // atomic

private:
    nlohmann::json json_;
};

}  // namespace bimslam::mapping
