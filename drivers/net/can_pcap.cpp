// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/net/can_pcap.hpp"

#include <cstdio>
#include <cstring>

#include "algorithms/common/status.hpp"
#include "drivers/net/byte_order.hpp"
#include "drivers/net/ipv4.hpp"

namespace bimslam::net {
namespace {
using detail::Be32;
using detail::Le32;

using common::CanFrame;
using common::Error;
using common::StatusCode;

constexpr uint8_t kCanFdFlagFdf = 0x04;  // CANFD_FDF
constexpr uint8_t kCanXlFlagXlf = 0x80;  // CANXL_XLF, in byte 4 of struct canxl_frame
constexpr uint32_t kMaxErrorClass = 0x7FF;
constexpr int kSocketcan = 0;
constexpr int kCooked = 1;

// The CAN part of a record: the bytes from the ID word on.
struct Payload {
    std::span<const uint8_t> bytes;
    int encapsulation = kSocketcan;
    bool fd = false;  // known to be CAN FD from outside the CAN header
};

CanDecodeResult Locate(const PcapRecord& record, Payload& out) {
    if (record.link_type == kLinkTypeCanSocketcan) {
        out.bytes = record.data;
        out.encapsulation = kSocketcan;
        out.fd = record.original_length == kCanFdMtu || record.data.size() == kCanFdMtu;
    } else if (record.link_type == kLinkTypeLinuxSll || record.link_type == kLinkTypeLinuxSll2) {
        LinkPayload link;
        const LinkResult result = ParseLinkLayer(record.link_type, record.data, link);
        if (result == LinkResult::kTruncated) return CanDecodeResult::kTruncated;
        if (result != LinkResult::kOk) return CanDecodeResult::kNotCan;
        if (link.ether_type == kSllProtocolCanXl) return CanDecodeResult::kCanXl;
        if (link.ether_type != kSllProtocolCan && link.ether_type != kSllProtocolCanFd) {
            return CanDecodeResult::kNotCan;
        }
        out.bytes = link.bytes;
        out.encapsulation = kCooked;
        out.fd = link.ether_type == kSllProtocolCanFd || link.bytes.size() == kCanFdMtu;
    } else {
        return CanDecodeResult::kNotCan;
    }
    if (out.bytes.size() >= 5 && (out.bytes[4] & kCanXlFlagXlf) != 0) {
        return CanDecodeResult::kCanXl;
    }
    if (out.bytes.size() < kCanRecordHeaderBytes) return CanDecodeResult::kTruncated;
    return CanDecodeResult::kFrame;
}

}  // namespace

std::string_view ToString(CanIdOrder order) {
    switch (order) {
        case CanIdOrder::kAuto:
            return "auto";
        case CanIdOrder::kBigEndian:
            return "big-endian";
        case CanIdOrder::kLittleEndian:
            return "little-endian";
    }
    return "unknown";
}

bool IsPlausibleCanId(uint32_t word) {
    if (word & common::kCanErrFlag) {
        return (word & (common::kCanEffFlag | common::kCanRtrFlag)) == 0 &&
               (word & common::kCanEffMask) <= kMaxErrorClass;
    }
    if (word & common::kCanEffFlag) return true;
    return (word & common::kCanEffMask) <= common::kCanSffMask;
}

void CanPcapConfig::Validate() const {
    if (id_order != CanIdOrder::kAuto && id_order != CanIdOrder::kBigEndian &&
        id_order != CanIdOrder::kLittleEndian) {
        throw Error(StatusCode::kInvalidArgument,
                    "id_order: not kAuto, kBigEndian or kLittleEndian");
    }
    if (detect_records < 1 || detect_records > 1'000'000) {
        throw Error(
            StatusCode::kInvalidArgument,
            "detect_records: " + std::to_string(detect_records) + ", must be in [1, 1000000]");
    }
}

CanRecordDecoder::CanRecordDecoder(const CanPcapConfig& config) : config_(config) {
    config_.Validate();
}

CanIdOrder CanRecordDecoder::Order(int encapsulation) const {
    if (config_.id_order != CanIdOrder::kAuto) return config_.id_order;
    const Votes& v = votes_[encapsulation];
    if (v.big != v.little)
        return v.big > v.little ? CanIdOrder::kBigEndian : CanIdOrder::kLittleEndian;
    return encapsulation == kSocketcan ? CanIdOrder::kBigEndian : CanIdOrder::kLittleEndian;
}

void CanRecordDecoder::Count(int encapsulation, uint32_t big, uint32_t little) {
    Votes& v = votes_[encapsulation];
    if (!detecting_ || v.records >= config_.detect_records) return;
    ++v.records;
    const bool b = IsPlausibleCanId(big);
    const bool l = IsPlausibleCanId(little);
    if (b && !l) ++v.big;
    if (l && !b) ++v.little;
}

void CanRecordDecoder::Vote(const PcapRecord& record) {
    Payload payload;
    if (Locate(record, payload) != CanDecodeResult::kFrame) return;
    const uint8_t* p = payload.bytes.data();
    Count(payload.encapsulation, Be32(p), Le32(p));
}

CanDecodeResult CanRecordDecoder::Decode(const PcapRecord& record, CanFrame& frame) {
    ++stats_.records;
    Payload payload;
    const CanDecodeResult located = Locate(record, payload);
    switch (located) {
        case CanDecodeResult::kFrame:
            break;
        case CanDecodeResult::kNotCan:
            ++stats_.not_can;
            return located;
        case CanDecodeResult::kCanXl:
            ++stats_.can_xl;
            return located;
        case CanDecodeResult::kTruncated:
            ++stats_.truncated;
            return located;
        default:
            return located;
    }
    const uint8_t* p = payload.bytes.data();
    const uint32_t big = Be32(p);
    const uint32_t little = Le32(p);
    Count(payload.encapsulation, big, little);

    // Rule 3: the file's order when plausible, else the other one (counted), else nothing.
    const bool big_ok = IsPlausibleCanId(big);
    const bool little_ok = IsPlausibleCanId(little);
    const CanIdOrder order = Order(payload.encapsulation);
    bool use_big = order == CanIdOrder::kBigEndian;
    bool disagrees = false;
    if (!(use_big ? big_ok : little_ok)) {
        if (config_.id_order != CanIdOrder::kAuto || !(use_big ? little_ok : big_ok)) {
            ++stats_.implausible_id;
            return CanDecodeResult::kImplausibleId;
        }
        use_big = !use_big;
        disagrees = true;
    }
    const uint32_t word = use_big ? big : little;

    const uint8_t len = p[4];
    const uint8_t flags = p[5];
    const bool remote = (word & common::kCanRtrFlag) != 0;
    const bool error = (word & common::kCanErrFlag) != 0;
    const bool fd = payload.fd || (flags & kCanFdFlagFdf) != 0 || len > 8;
    if (len > 64 || (fd && (remote || error || !common::IsCanFdLength(len))) ||
        ((remote || error) && len > 8)) {
        ++stats_.malformed;
        return CanDecodeResult::kMalformed;
    }
    if (!remote && payload.bytes.size() < kCanRecordHeaderBytes + len) {
        ++stats_.truncated;
        return CanDecodeResult::kTruncated;
    }

    frame = CanFrame{};
    frame.timestamp_ns = record.timestamp_ns;
    frame.error = error;
    frame.remote = remote;
    frame.extended = !error && (word & common::kCanEffFlag) != 0;
    frame.id = word & (frame.extended || error ? common::kCanEffMask : common::kCanSffMask);
    frame.fd = fd;
    frame.len = len;
    if (fd) {
        frame.fd_flags = flags & common::kCanFdFlagsMask;
    } else if (len == 8 && p[7] >= 9 && p[7] <= 15) {
        frame.len8_dlc = p[7];
    }
    if (!remote) std::memcpy(frame.data.data(), p + kCanRecordHeaderBytes, len);

    ++stats_.frames;
    ++(use_big ? stats_.big_endian_ids : stats_.little_endian_ids);
    if (big_ok && little_ok) ++stats_.ambiguous_ids;
    if (disagrees) ++stats_.order_disagreements;
    return CanDecodeResult::kFrame;
}

size_t EncodeCanSocketcan(const CanFrame& frame, std::span<uint8_t> out) {
    const size_t size = frame.fd ? kCanFdMtu : kCanMtu;
    if (out.size() < size || common::CanFrameProblem(frame) != nullptr ||
        (frame.error && frame.id > kMaxErrorClass)) {
        return 0;
    }
    uint32_t word = frame.id;
    if (frame.extended) word |= common::kCanEffFlag;
    if (frame.remote) word |= common::kCanRtrFlag;
    if (frame.error) word |= common::kCanErrFlag;
    std::memset(out.data(), 0, size);
    out[0] = static_cast<uint8_t>(word >> 24);
    out[1] = static_cast<uint8_t>(word >> 16);
    out[2] = static_cast<uint8_t>(word >> 8);
    out[3] = static_cast<uint8_t>(word);
    out[4] = frame.len;
    out[5] = frame.fd ? frame.fd_flags : 0;
    out[7] = frame.len8_dlc;
    if (!frame.remote)
        std::memcpy(out.data() + kCanRecordHeaderBytes, frame.data.data(), frame.len);
    return size;
}

void WriteCanFrame(PcapWriter& writer, const CanFrame& frame) {
    uint8_t bytes[kCanFdMtu];
    const size_t n = EncodeCanSocketcan(frame, bytes);
    if (n == 0) {
        const char* problem = common::CanFrameProblem(frame);
        char id[16];
        std::snprintf(id, sizeof(id), "0x%X", frame.id);
        throw Error(StatusCode::kInvalidArgument,
                    writer.name() + ": cannot write the CAN frame with id " + id + ": " +
                        (problem != nullptr ? problem
                                            : "error class bits above 0x7FF (not readable back)"));
    }
    writer.WriteRecord(frame.timestamp_ns, std::span<const uint8_t>(bytes, n));
}

CanPcapReader::CanPcapReader(PcapReader reader, const CanPcapConfig& config)
    : reader_(std::move(reader)), decoder_(config) {}

void CanPcapReader::Detect(PcapReader& ahead) {
    if (decoder_.config().id_order == CanIdOrder::kAuto) {
        try {
            PcapRecord r;
            for (size_t i = 0; i < decoder_.config().detect_records && ahead.Next(r); ++i) {
                decoder_.Vote(r);
            }
        } catch (const common::FileError&) {
            // The main pass reports it, after the records before it.
        }
    }
    decoder_.FinishDetection();
}

CanPcapReader::CanPcapReader(const std::filesystem::path& path, const CanPcapConfig& config)
    : CanPcapReader(PcapReader(path), config) {
    if (config.id_order == CanIdOrder::kAuto) {
        try {
            PcapReader ahead(path);
            Detect(ahead);
        } catch (const common::FileError&) {
            // As in Detect.
        }
    }
    decoder_.FinishDetection();
}

CanPcapReader CanPcapReader::FromMemory(std::string name, std::span<const uint8_t> bytes,
                                        const CanPcapConfig& config) {
    CanPcapReader reader(PcapReader::FromMemory(name, bytes), config);
    PcapReader ahead = PcapReader::FromMemory(std::move(name), bytes);
    reader.Detect(ahead);
    return reader;
}

bool CanPcapReader::Next(CanFrame& frame) {
    while (reader_.Next(record_)) {
        if (decoder_.Decode(record_, frame) == CanDecodeResult::kFrame) return true;
    }
    return false;
}

}  // namespace bimslam::net
