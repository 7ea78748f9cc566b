// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A CAN recording read back, whatever its format: a candump -l text log or a pcap/pcapng of
// SocketCAN (link type 227) or Linux cooked frames, plain or gzipped, told apart by content.
// Bad candump lines are skipped and counted (lenient), as a tool looking at a log wants.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "algorithms/common/can_frame.hpp"

namespace bimslam::capture {

class CanLog {
public:
    // Throws common::FileError naming the file when it cannot be read or has a corrupt header.
    explicit CanLog(const std::filesystem::path& path);
    ~CanLog();

    bool Next(common::CanFrame& frame);

    // "candump", "pcap", "pcapng", with ".gz" appended for gzipped input.
    const std::string& format() const { return format_; }
    bool truncated() const;
    // Records or lines skipped, by cause ("garbage", "bad_length", "not_can", ...).
    std::map<std::string, uint64_t> Skipped() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::string format_;
};

}  // namespace bimslam::capture
