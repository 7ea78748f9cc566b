// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/capture/can_log.hpp"

#include <zlib.h>

#include <array>
#include <optional>

#include "algorithms/common/status.hpp"
#include "drivers/can/candump.hpp"
#include "drivers/net/can_pcap.hpp"
#include "drivers/net/pcap_reader.hpp"

namespace bimslam::capture {
namespace {
// The first bytes of the (decompressed) content, and whether the file is gzipped.
std::pair<std::array<uint8_t, 4>, bool> Peek(const std::filesystem::path& path) {
    std::array<uint8_t, 4> head{};
    gzFile f = gzopen(path.c_str(), "rb");
    if (f == nullptr) {
        throw common::FileError(common::StatusCode::kNotFound, path.string(), 0, "cannot open");
    }
    const int n = gzread(f, head.data(), head.size());
    const bool gz = gzdirect(f) == 0;
    gzclose(f);
    if (n < 0) {
        throw common::FileError(common::StatusCode::kIoError, path.string(), 0, "cannot read");
    }
    return {head, gz};
}

}  // namespace

struct CanLog::Impl {
    std::optional<can::CandumpReader> candump;
    std::optional<net::CanPcapReader> pcap;
};

CanLog::CanLog(const std::filesystem::path& path) : impl_(std::make_unique<Impl>()) {
    const bool gz = Peek(path).second;  // also: unreadable files throw here
    if (net::LooksLikePcap(path)) {
        impl_->pcap.emplace(path);
        format_ = impl_->pcap->pcap().format() == net::PcapFormat::kPcapNg ? "pcapng" : "pcap";
    } else {
        can::CandumpReaderConfig config;
        config.mode = can::CandumpMode::kLenient;
        impl_->candump.emplace(path, config);
        format_ = "candump";
    }
    if (gz) format_ += ".gz";
}

CanLog::~CanLog() = default;

bool CanLog::Next(common::CanFrame& frame) {
    if (impl_->pcap) return impl_->pcap->Next(frame);
    can::CandumpRecord record;
    if (!impl_->candump->Next(record)) return false;
    frame = record.frame;
    return true;
}

bool CanLog::truncated() const {
    return impl_->pcap ? impl_->pcap->pcap().truncated() : impl_->candump->truncated();
}

std::map<std::string, uint64_t> CanLog::Skipped() const {
    std::map<std::string, uint64_t> out;
    if (impl_->pcap) {
        const net::CanPcapStats& s = impl_->pcap->stats();
        out["not_can"] = s.not_can;
        out["can_xl"] = s.can_xl;
        out["truncated_record"] = s.truncated;
        out["malformed"] = s.malformed;
        out["implausible_id"] = s.implausible_id;
        return out;
    }
    const can::CandumpStats& s = impl_->candump->stats();
    for (size_t i = 0; i < can::kCandumpIssueCount; ++i) {
        out[std::string(can::ToString(static_cast<can::CandumpIssue>(i)))] = s.skipped[i];
    }
    return out;
}

}  // namespace bimslam::capture
