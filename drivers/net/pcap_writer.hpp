// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Classic pcap writer (pcap-savefile(5), draft-ietf-opsawg-pcap), for the capture simulator, for
// tests, and for CAN recordings (link type 227, records written raw). libpcap writes the file
// (pcap_open_dead_with_tstamp_precision for the link type, snaplen and precision, pcap_dump_fopen,
// pcap_dump); this class builds the frames.
//
// WriteUdp builds the frames a Linux host would put on the wire for one UDP datagram: Ethernet
// (or no link header for the raw/IPv4 link types), an IPv4 header with the right checksum and an
// identification that increments per datagram, a UDP header with the right checksum, and, when
// the datagram does not fit `mtu`, IPv4 fragments cut as ip_do_fragment (net/ipv4/ip_output.c)
// cuts them: every fragment but the last carries (mtu - 20) rounded down to a multiple of 8 bytes
// of IP payload, in ascending offset order, the UDP header in the first.
//
// Output goes through a 256 KiB stdio buffer. The file is written as a stream, not atomically: a
// writer killed half-way leaves a truncated capture, which PcapReader reads up to the cut, as it
// does with a killed tcpdump. Call Close() to see write errors (the destructor closes quietly).
// Link types are those of tcpdump.org/linktypes.html, as in the file; libpcap writes the ones it
// knows (up to 289 in libpcap 1.10), and the constructor throws for others.
#pragma once

#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "drivers/net/pcap_reader.hpp"

struct pcap;         // libpcap's pcap_t
struct pcap_dumper;  // libpcap's pcap_dumper_t

namespace bimslam::net {

struct PcapWriterConfig {
    uint32_t link_type = kLinkTypeEthernet;
    bool nanosecond = true;  // magic A1B23C4D; false: A1B2C3D4 and microseconds (truncated)
    uint32_t snaplen = PcapReader::kMaxCaptureBytes;  // longer records are cut, as tcpdump -s does
    // For WriteUdp.
    std::array<uint8_t, 6> source_mac{0x02, 0, 0, 0, 0, 0x01};  // locally administered
    std::array<uint8_t, 6> destination_mac{0x02, 0, 0, 0, 0, 0x02};
    uint8_t ttl = 64;
    uint16_t first_ip_id = 1;
    // true: the UDP checksum over pseudo-header, header and payload (0 sent as 0xFFFF); false: 0,
    // "no checksum" (RFC 768), which receivers accept.
    bool udp_checksum = true;

    // Throws common::Error (kInvalidArgument) naming the field.
    void Validate() const;
};

class PcapWriter {
public:
    // Creates (truncates) `path` and writes the file header. Throws common::FileError naming the
    // file, or when libpcap cannot write the link type.
    PcapWriter(const std::filesystem::path& path, const PcapWriterConfig& config = {});
    // Writes into memory (bytes()); `name` is used in messages.
    explicit PcapWriter(const PcapWriterConfig& config = {}, std::string name = "<memory>");
    PcapWriter(const PcapWriter&) = delete;
    PcapWriter& operator=(const PcapWriter&) = delete;
    ~PcapWriter();

    // One record as it is (caplen = min(size, snaplen), original length = size, or
    // `original_length` when larger). `timestamp_ns` must lie in [0, 2^32 s).
    void WriteRecord(int64_t timestamp_ns, std::span<const uint8_t> bytes,
                     uint32_t original_length = 0);
    // One UDP datagram as one or more IPv4 packets (see the file comment); all records get the
    // same timestamp. `mtu` is the IPv4 packet size limit (1500 on Ethernet); 0: never fragment.
    // Throws common::Error (kInvalidArgument) for a payload above 65507 bytes, an mtu below 28
    // (other than 0), or a link type other than Ethernet, raw or IPv4.
    void WriteUdp(int64_t timestamp_ns, uint32_t src_ip, uint16_t src_port, uint32_t dst_ip,
                  uint16_t dst_port, std::span<const uint8_t> payload, uint32_t mtu = 0);

    // Writes what is buffered; throws common::FileError naming the file.
    void Flush();
    // Flush and close; throws common::FileError naming the file. Further writes are errors.
    void Close();

    // The file so far (memory writer only; Flush is not needed).
    const std::string& bytes() const { return memory_; }
    uint64_t records() const { return records_; }
    uint16_t next_ip_id() const { return next_ip_id_; }
    const std::string& name() const { return name_; }

private:
    void Open(FILE* file);
    [[noreturn]] void Fail(const std::string& what) const;

    PcapWriterConfig config_;
    std::string name_;
    bool closed_ = false;
    std::vector<char> buffer_;  // the stream's; outlives it
    std::string memory_;        // appended to by the memory stream, unbuffered
    FILE* file_ = nullptr;      // owned by dumper_ once it is open
    pcap* dead_ = nullptr;      // the link type, snaplen and precision for libpcap
    pcap_dumper* dumper_ = nullptr;
    std::vector<uint8_t> frame_;  // one packet being built
    uint64_t records_ = 0;
    uint16_t next_ip_id_ = 1;
};

}  // namespace bimslam::net
