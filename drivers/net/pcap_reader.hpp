// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Packet capture files: classic pcap and pcapng, plain or gzip-compressed, streamed record by
// record.
//
// Classic pcap (draft-ietf-opsawg-pcap; pcap-savefile(5): µs and ns magics, both byte orders,
// and the modified format of Kuznetsov's patched libpcap) is read by libpcap
// (pcap_fopen_offline_with_tstamp_precision at nanosecond precision, pcap_next_ex) from a stdio
// stream: the file itself, zlib behind fopencookie(3) for a .gz, fmemopen(3) for FromMemory.
// pcapng (draft-ietf-opsawg-pcapng) is read by a block reader of ours (pcapng_reader.hpp says
// why: libpcap refuses interfaces of different link types in one file, and sections of different
// byte orders).
//
// The reader returns every record as captured, whatever its link type: Ethernet and Linux cooked
// records go to UdpExtractor (ipv4.hpp), SocketCAN records (link type 227, and CAN inside Linux
// cooked captures) to the CAN driver (specs/go1-can.md, "Recording and replay").
//
// Errors: a corrupt header (bad magic, a capture length above kMaxCaptureBytes, a bad block
// length) throws common::FileError naming the file, the byte offset and what is wrong (with
// libpcap's own message where libpcap found it); the records before it have been delivered. A
// file that ends inside a record is not an error: a killed capture is normal. The stream ends
// cleanly and truncated() says so.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>

namespace bimslam::net {

// Link types (https://www.tcpdump.org/linktypes.html).
inline constexpr uint32_t kLinkTypeNull = 0;            // BSD loopback: 4-byte address family
inline constexpr uint32_t kLinkTypeEthernet = 1;        // IEEE 802.3 Ethernet
inline constexpr uint32_t kLinkTypeRaw = 101;           // raw IPv4 or IPv6, no link header
inline constexpr uint32_t kLinkTypeLoop = 108;          // OpenBSD loopback: big-endian family
inline constexpr uint32_t kLinkTypeLinuxSll = 113;      // Linux cooked capture v1 (tcpdump -i any)
inline constexpr uint32_t kLinkTypeCanSocketcan = 227;  // SocketCAN frame with 8-byte header
inline constexpr uint32_t kLinkTypeIpv4 = 228;          // raw IPv4
inline constexpr uint32_t kLinkTypeLinuxSll2 = 276;     // Linux cooked capture v2

// One captured packet. `data` points into the reader's (or libpcap's) buffer, or into the
// caller's memory for FromMemory, and stays valid until the next call to PcapReader::Next.
struct PcapRecord {
    int64_t timestamp_ns = 0;       // capture time, UNIX epoch (the capturing host's clock)
    uint32_t link_type = 0;         // of the file (classic) or of the record's interface (pcapng)
    uint32_t interface_id = 0;      // pcapng interface within its section; 0 for classic pcap
    uint32_t original_length = 0;   // length on the wire; may exceed data.size() (snaplen)
    std::span<const uint8_t> data;  // the captured bytes
    uint64_t index = 0;             // 0-based record number in the file
    uint64_t file_offset = 0;       // byte offset of the record header (pcapng: block) in the file,
                                    // counted in decompressed bytes for a .gz file
};

enum class PcapFormat : uint8_t { kPcap, kPcapNg };

// True when the file (gzipped or not) starts with a classic pcap or pcapng magic: how a reader of
// "a CAN recording" tells a pcap from a candump text log. False when it cannot be read.
bool LooksLikePcap(const std::filesystem::path& path);

class PcapReader {
public:
    // Largest caplen and classic snaplen accepted: libpcap's MAXIMUM_SNAPLEN (262144). Larger
    // values only come from corrupt headers.
    static constexpr uint32_t kMaxCaptureBytes = 256 * 1024;
    // Largest pcapng block that is loaded (packet blocks, section and interface headers); other
    // blocks are skipped whatever their size.
    static constexpr uint32_t kMaxLoadedBlockBytes = 1024 * 1024;

    // Opens a .pcap/.pcapng file, gzip-compressed or not (told by the gzip magic), and reads the
    // file header. Throws common::FileError naming the file when it cannot be
    // opened or its header is not a pcap/pcapng header.
    explicit PcapReader(const std::filesystem::path& path);
    // Reads from memory the caller keeps alive (not gzip); `name` is used in error messages.
    static PcapReader FromMemory(std::string name, std::span<const uint8_t> bytes);
    static PcapReader FromMemory(std::string name, std::string_view bytes);

    PcapReader(PcapReader&&) noexcept;
    PcapReader& operator=(PcapReader&&) noexcept;
    ~PcapReader();

    // The next record, or false at the end of the file (also when the file ends inside a record:
    // see truncated()). Throws common::FileError on a corrupt header. Allocates nothing of ours;
    // libpcap grows its record buffer by powers of two up to the snaplen during the first records
    // (at most 7 times from its initial 2 KiB), then reuses it.
    bool Next(PcapRecord& record);

    // True when the file ended inside a record or block header or body (a capture that was
    // killed, a cut download), or a gzip stream ended before its trailer.
    bool truncated() const;
    // How many bytes of the incomplete last record were there (0 when not truncated).
    uint64_t truncated_bytes() const;
    // Records returned so far.
    uint64_t records() const;
    // pcapng blocks skipped (name resolution, statistics, custom, unknown types, ...).
    uint64_t skipped_blocks() const;

    PcapFormat format() const;
    // Classic pcap: the file's link type and snaplen. pcapng: those of the first interface,
    // known after the constructor when interface blocks follow the section header (as libpcap,
    // dumpcap and Wireshark write them), else once Next() has read one (0 until then).
    uint32_t link_type() const;
    uint32_t snaplen() const;
    // Classic pcap: true for the nanosecond magic. pcapng: false (per-interface if_tsresol).
    bool nanosecond() const;
    const std::string& name() const;

private:
    struct State;
    explicit PcapReader(std::unique_ptr<State> state);
    std::unique_ptr<State> state_;
};

}  // namespace bimslam::net
