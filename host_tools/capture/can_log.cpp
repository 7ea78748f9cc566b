#include "host_tools/capture/can_log.hpp"

#include <zlib.h>

#include <array>
#include <optional>

#include "algorithms/common/status.hpp"
#include "drivers/can/candump.hpp"
#include "drivers/net/can_pcap.hpp"

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

bool IsPcapMagic(const std::array<uint8_t, 4>& h, bool* pcapng) {
    const uint32_t le = h[0] | h[1] << 8 | h[2] << 16 | uint32_t(h[3]) << 24;
    const uint32_t be = h[3] | h[2] << 8 | h[1] << 16 | uint32_t(h[0]) << 24;
    *pcapng = le == 0x0A0D0D0A;
    for (uint32_t magic : {0xA1B2C3D4u, 0xA1B23C4Du}) {
        if (le == magic || be == magic) return true;
    }
    return *pcapng;
}
}  // namespace

struct CanLog::Impl {
    std::optional<can::CandumpReader> candump;
    std::optional<net::CanPcapReader> pcap;
};

CanLog::CanLog(const std::filesystem::path& path) : impl_(std::make_unique<Impl>()) {
    const auto [head, gz] = Peek(path);
    bool pcapng = false;
    if (IsPcapMagic(head, &pcapng)) {
        impl_->pcap.emplace(path);
        format_ = pcapng ? "pcapng" : "pcap";
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
