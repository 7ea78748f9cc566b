// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Internal to drivers/net: pcapng (draft-ietf-opsawg-pcapng), read block by block, behind
// PcapReader.
//
// libpcap reads pcapng too, but not the files this reader accepts: libpcap 1.10 stops with an
// error at an interface whose link type or snapshot length differs from the first interface's
// ("an interface has a type 276 different from the type of the first interface"), which is what
// dumpcap and Wireshark write when they capture on several interfaces (Ethernet and a CAN bus),
// and at a section whose byte order differs from the first section's ("the file has sections
// with different byte orders"). Records also carry the offset of their block, which libpcap's
// API does not give. So pcapng stays ours; classic pcap is read by libpcap (pcap_reader.cpp).
//
// Blocks are (type, total length, body, total length again); a Section Header Block sets the
// byte order, Interface Description Blocks the link type and timestamp resolution (if_tsresol)
// and offset (if_tsoffset) of each interface; packets come in Enhanced, Simple and (obsolete)
// Packet Blocks; other blocks are skipped.
#pragma once

#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include "drivers/net/capture_file.hpp"
#include "drivers/net/pcap_reader.hpp"

namespace bimslam::net::detail {

class PcapNgReader {
public:
    // From a stream the caller keeps open (OpenCaptureFile), or from memory the caller keeps
    // alive. Reads the section header and the interface blocks that follow it; throws
    // common::FileError naming `name` and the byte offset when they are corrupt.
    PcapNgReader(std::string name, FILE* file, const GzipStatus* gzip);
    PcapNgReader(std::string name, std::span<const uint8_t> bytes);

    // As PcapReader::Next; `records` is the number of records returned before.
    bool Next(PcapRecord& record, uint64_t records);

    bool truncated() const { return truncated_; }
    uint64_t truncated_bytes() const { return truncated_bytes_; }
    uint64_t skipped_blocks() const { return skipped_blocks_; }
    // Of the first interface (0 until one has been read).
    uint32_t link_type() const { return link_type_; }
    uint32_t snaplen() const { return snaplen_; }

private:
    struct Interface {
        uint32_t link_type = 0;
        uint32_t snaplen = 0;
        uint8_t tsresol = 6;  // if_tsresol: default 10^-6 s
        int64_t tsoffset_s = 0;
    };

    uint64_t Offset() const { return data_offset_ + pos_; }
    size_t Available() const { return size_ - pos_; }
    [[noreturn]] void Fail(uint64_t offset, const std::string& what) const;
    [[noreturn]] void ReadError() const;
    uint16_t U16(const uint8_t* p) const;
    uint32_t U32(const uint8_t* p) const;
    bool Ensure(size_t n);
    bool Skip(uint64_t n);
    bool EndTruncated();
    void ReadByteOrder(uint64_t offset);
    void CheckTrailer(const uint8_t* block, uint32_t length, uint64_t offset) const;
    void ReadFileHeader();
    void ReadSectionHeader(const uint8_t* block, uint32_t length, uint64_t offset);
    void ReadInterface(const uint8_t* block, uint32_t length, uint64_t offset);
    int64_t Time(const Interface& itf, uint32_t high, uint32_t low, uint64_t offset) const;

    std::string name_;
    // Input: a stream read into `buffer_`, or the caller's memory.
    FILE* file_ = nullptr;
    const GzipStatus* gzip_ = nullptr;
    std::vector<uint8_t> buffer_;
    const uint8_t* data_ = nullptr;
    size_t size_ = 0;           // valid bytes at data_
    size_t pos_ = 0;            // next unread byte at data_
    uint64_t data_offset_ = 0;  // file offset of data_[0]
    bool eof_ = false;

    bool swapped_ = false;  // the section's byte order differs from this host's (little-endian)
    uint32_t link_type_ = 0;
    uint32_t snaplen_ = 0;
    std::vector<Interface> interfaces_;  // of the current section

    uint64_t skipped_blocks_ = 0;
    bool truncated_ = false;
    uint64_t truncated_bytes_ = 0;
    bool done_ = false;
};

}  // namespace bimslam::net::detail
