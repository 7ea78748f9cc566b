// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// libFuzzer target: PcapReader (from memory) + CAN record decoding (drivers/net/can_pcap.hpp)
// over arbitrary bytes: a bare CanRecordDecoder (votes as it goes) and a CanPcapReader (reads
// ahead). They must end cleanly or throw common::FileError; every decoded frame must be valid,
// encode, and decode back to itself; every record must be returned or counted. Anything else is a
// finding. Seeds (corpus/can_pcap_fuzz): small captures our PcapWriter wrote (link types 227 with
// both ID byte orders, SLL, SLL2).
#include <cstddef>
#include <cstdint>
#include <span>

#include "algorithms/common/can_frame.hpp"
#include "algorithms/common/status.hpp"
#include "drivers/net/can_pcap.hpp"
#include "drivers/net/pcap_reader.hpp"

namespace {

using bimslam::common::CanFrame;

bool SameFrame(const CanFrame& a, const CanFrame& b) {
    return a.timestamp_ns == b.timestamp_ns && a.id == b.id && a.extended == b.extended &&
           a.remote == b.remote && a.error == b.error && a.fd == b.fd && a.len == b.len &&
           a.fd_flags == b.fd_flags && a.len8_dlc == b.len8_dlc && a.data == b.data;
}

void CheckFrame(const CanFrame& frame) {
    using namespace bimslam;
    if (common::CanFrameProblem(frame) != nullptr) __builtin_trap();
    uint8_t bytes[net::kCanFdMtu];
    const size_t n = net::EncodeCanSocketcan(frame, bytes);
    if (n == 0) __builtin_trap();
    net::PcapRecord record;
    record.link_type = net::kLinkTypeCanSocketcan;
    record.timestamp_ns = frame.timestamp_ns;
    record.data = std::span<const uint8_t>(bytes, n);
    record.original_length = static_cast<uint32_t>(n);
    net::CanPcapConfig config;
    config.id_order = net::CanIdOrder::kBigEndian;
    net::CanRecordDecoder decoder(config);
    CanFrame again;
    if (decoder.Decode(record, again) != net::CanDecodeResult::kFrame) __builtin_trap();
    if (!SameFrame(again, frame)) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace bimslam;
    const std::span<const uint8_t> input(data, size);
    try {
        net::PcapReader reader = net::PcapReader::FromMemory("fuzz.pcap", input);
        net::CanRecordDecoder decoder;
        net::PcapRecord record;
        CanFrame frame;
        while (reader.Next(record)) {
            if (decoder.Decode(record, frame) == net::CanDecodeResult::kFrame) CheckFrame(frame);
        }
        const net::CanPcapStats& s = decoder.stats();
        if (s.records != reader.records() ||
            s.records !=
                s.frames + s.not_can + s.can_xl + s.truncated + s.malformed + s.implausible_id ||
            s.frames != s.big_endian_ids + s.little_endian_ids) {
            __builtin_trap();  // a record neither returned nor counted
        }
    } catch (const common::FileError&) {
    }
    try {
        net::CanPcapReader reader = net::CanPcapReader::FromMemory("fuzz.pcap", input);
        CanFrame frame;
        while (reader.Next(frame)) CheckFrame(frame);
    } catch (const common::FileError&) {
    }
    return 0;
}
