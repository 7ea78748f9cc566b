// What a step of `bimslam map` was made from, so that a re-run can skip it: its inputs' identity
// (the model by SHA-256, recordings by size and modification time: hashing gigabytes of pcap on
// every run would cost more than some steps), the stamps of the steps it read, and its parameters.
// A step is up to date when its stamp file holds exactly the stamp a run would write now.
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
    // A file identified by size and modification time (nanoseconds); a missing file is noted
    // as missing (its appearance changes the stamp).
    void AddFileTime(const std::string& key, const std::filesystem::path& file);
    // The stamp of a step this one read: a change there changes this one.
    void AddUpstream(const StepStamp& upstream);
    void AddParameter(const std::string& key, nlohmann::json value);

    const nlohmann::json& json() const { return json_; }
    // SHA-256 of the stamp's text: what downstream stamps hold.
    std::string Digest() const;

    // True when `file` holds this stamp. A missing or unreadable file is not up to date.
    bool Matches(const std::filesystem::path& file) const;
    void Write(const std::filesystem::path& file) const;  // atomic

private:
    nlohmann::json json_;
};

}  // namespace bimslam::mapping
