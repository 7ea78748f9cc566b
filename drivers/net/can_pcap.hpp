// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// CAN frames in packet captures (specs/go1-can.md, "Recording and replay"): decoding pcap records
// into common::CanFrame and encoding frames into records.
//
// Encapsulations read:
// - LINKTYPE_CAN_SOCKETCAN (227, https://www.tcpdump.org/linktypes/LINKTYPE_CAN_SOCKETCAN.html):
//   a 4-byte CAN ID word (flags EFF 0x80000000, RTR 0x40000000, ERR 0x20000000, then the 11- or
//   29-bit identifier or the error class bits), the payload length, the FD flags (BRS 0x1,
//   ESI 0x2, FDF 0x4), two reserved bytes (the last one len8_dlc for classic frames), the data.
//   The standard stores the ID word big-endian; older libpcap versions and other writers stored
//   it in the capturing host's order (little-endian in the gmlan capture of ../shared/data/can).
// - Linux cooked captures, SLL (113) and SLL2 (276), with protocol 0x000C (CAN) or 0x000D
//   (CAN FD): the same layout after the cooked header, the ID word in the host's order.
// CAN FD is told by the FDF flag, a length above 8, a record of exactly 72 bytes (struct
// canfd_frame, as the kernel hands it to tcpdump and as Wireshark decides) or protocol 0x000D.
// CAN XL (the XLF flag 0x80 in byte 4, protocol 0x000E) and every other record are skipped and
// counted.
//
// The byte order of the ID word (CanIdOrder::kAuto), decided per file and per encapsulation
// (227 apart from SLL/SLL2):
// 1. A word is plausible (IsPlausibleCanId) when it is an error frame (ERR without EFF or RTR,
//    error class bits within 0x7FF; the kernel defines bits up to 0x200), an extended frame (EFF,
//    any 29-bit identifier), or a standard frame whose identifier fits 11 bits. A standard id in
//    the wrong byte order puts its low byte into the flag bits and the identifier range, so
//    almost every standard frame is plausible in one order only; extended frames often in both.
// 2. A record plausible in exactly one order is a vote for that order. The file's order is the
//    one with more votes among the first CanPcapConfig::detect_records records (CanPcapReader
//    reads them ahead, before returning the first frame; a bare CanRecordDecoder counts the
//    votes of the records it decodes, so its order can still change during those records).
//    No votes or a tie: big-endian for 227 (the standard), little-endian for SLL (host order of
//    x86-64 and ARM64).
// 3. Each record is decoded in the file's order when the word is plausible that way; when it is
//    plausible only the other way it is decoded the other way and counted in
//    order_disagreements; when plausible in neither it is skipped (implausible_id).
// A fixed order (kBigEndian, kLittleEndian) decodes every record that way; implausible words are
// skipped all the same.
//
// Encoding writes link type 227 as the kernel hands frames to tcpdump: the ID word big-endian (the
// standard), 16-byte records for classic frames (struct can_frame), 72-byte ones for CAN FD
// (struct canfd_frame), the FD flags as the frame holds them.
//
// Decoding: no allocation, no exceptions; every skipped record is counted in CanPcapStats.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

#include "algorithms/common/can_frame.hpp"
#include "drivers/net/pcap_reader.hpp"
#include "drivers/net/pcap_writer.hpp"

namespace bimslam::net {

inline constexpr uint16_t kSllProtocolCan = 0x000C;    // ETH_P_CAN
inline constexpr uint16_t kSllProtocolCanFd = 0x000D;  // ETH_P_CANFD
inline constexpr uint16_t kSllProtocolCanXl = 0x000E;  // ETH_P_CANXL (not decoded)
inline constexpr size_t kCanRecordHeaderBytes = 8;
inline constexpr size_t kCanMtu = 16;    // sizeof(struct can_frame)
inline constexpr size_t kCanFdMtu = 72;  // sizeof(struct canfd_frame)

enum class CanIdOrder : uint8_t { kAuto, kBigEndian, kLittleEndian };
std::string_view ToString(CanIdOrder order);

// Rule 1 of the file comment.
bool IsPlausibleCanId(uint32_t word);

enum class CanDecodeResult : uint8_t {
    kFrame,          // `frame` holds a frame
    kNotCan,         // another link type, or SLL with another protocol
    kCanXl,          // a CAN XL frame
    kTruncated,      // shorter than its headers or than header + length (snaplen)
    kMalformed,      // length above 64, CAN FD length no DLC gives, remote or error frame > 8 / FD
    kImplausibleId,  // the ID word is plausible in no byte order (or not in the fixed one)
};

struct CanPcapConfig {
    CanIdOrder id_order = CanIdOrder::kAuto;
    // Records whose votes decide the byte order (rule 2).
    size_t detect_records = 256;

    // Throws common::Error (kInvalidArgument) naming the field.
    void Validate() const;
};

struct CanPcapStats {
    uint64_t records = 0;              // records decoded
    uint64_t frames = 0;               // frames returned
    uint64_t not_can = 0;              // skipped: other link types, SLL of other protocols
    uint64_t can_xl = 0;               // skipped: CAN XL
    uint64_t truncated = 0;            // skipped: cut short
    uint64_t malformed = 0;            // skipped: impossible lengths and combinations
    uint64_t implausible_id = 0;       // skipped: rule 3
    uint64_t big_endian_ids = 0;       // frames whose ID word was read big-endian
    uint64_t little_endian_ids = 0;    // frames whose ID word was read little-endian
    uint64_t ambiguous_ids = 0;        // frames plausible in both orders (read in the file's)
    uint64_t order_disagreements = 0;  // frames plausible only against the file's order
};

// Decodes the records of one file (its byte-order decision is per file: one decoder a file).
class CanRecordDecoder {
public:
    // Throws common::Error for a bad configuration.
    explicit CanRecordDecoder(const CanPcapConfig& config = {});

    // Counts the record's vote on the byte order without decoding it (reading ahead).
    void Vote(const PcapRecord& record);
    // Freezes the byte order decision: Decode votes no more.
    void FinishDetection() { detecting_ = false; }

    // Decodes one record; `frame` is written only for kFrame. Never throws, never allocates.
    CanDecodeResult Decode(const PcapRecord& record, common::CanFrame& frame);

    // The order decided (so far) for link type 227, and for SLL/SLL2.
    CanIdOrder socketcan_order() const { return Order(0); }
    CanIdOrder cooked_order() const { return Order(1); }
    const CanPcapStats& stats() const { return stats_; }
    const CanPcapConfig& config() const { return config_; }

private:
    struct Votes {
        uint64_t records = 0;  // CAN records looked at
        uint64_t big = 0;      // plausible big-endian only
        uint64_t little = 0;   // plausible little-endian only
    };
    CanIdOrder Order(int encapsulation) const;
    void Count(int encapsulation, uint32_t big, uint32_t little);

    CanPcapConfig config_;
    bool detecting_ = true;
    Votes votes_[2];
    CanPcapStats stats_;
};

// Link type 227 record bytes for `frame` (see the file comment) into `out`: returns 16 or 72, or 0
// when `out` is shorter or the frame cannot be encoded (common::CanFrameProblem, or error class
// bits above 0x7FF, which rule 1 would not read back). No allocation.
size_t EncodeCanSocketcan(const common::CanFrame& frame, std::span<uint8_t> out);

// Writes `frame` as one record (its timestamp_ns as capture time) to a writer created with
// link_type = kLinkTypeCanSocketcan. Throws common::Error (kInvalidArgument) naming what is wrong
// with a frame EncodeCanSocketcan refuses, and what PcapWriter::WriteRecord throws.
void WriteCanFrame(PcapWriter& writer, const common::CanFrame& frame);

// A CAN capture read back: PcapReader + CanRecordDecoder, the byte order decided from the first
// detect_records records (read once ahead, through a second reader) before the first frame.
class CanPcapReader {
public:
    // Throws what PcapReader throws, and common::Error for a bad configuration.
    explicit CanPcapReader(const std::filesystem::path& path, const CanPcapConfig& config = {});
    // Reads memory the caller keeps alive (not gzip); `name` is used in error messages.
    static CanPcapReader FromMemory(std::string name, std::span<const uint8_t> bytes,
                                    const CanPcapConfig& config = {});

    // The next frame, skipping (and counting) records that are not; false at the end of the file.
    // Throws common::FileError as PcapReader::Next does.
    bool Next(common::CanFrame& frame);

    const CanPcapStats& stats() const { return decoder_.stats(); }
    const CanRecordDecoder& decoder() const { return decoder_; }
    const PcapReader& pcap() const { return reader_; }

private:
    CanPcapReader(PcapReader reader, const CanPcapConfig& config);
    void Detect(PcapReader& ahead);

    PcapReader reader_;
    CanRecordDecoder decoder_;
    PcapRecord record_;
};

}  // namespace bimslam::net
