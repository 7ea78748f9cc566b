// Packet capture files: classic pcap and pcapng, plain or gzip-compressed, streamed record by
// record.
//
// Formats: classic pcap as libpcap writes it (draft-ietf-opsawg-pcap; pcap-savefile(5)): a 24-byte
// file header whose magic gives the byte order and the timestamp unit (0xA1B2C3D4 microseconds,
// 0xA1B23C4D nanoseconds), then 16-byte record headers (ts_sec, ts_frac, caplen, len) each
// followed by caplen bytes. pcapng (draft-ietf-opsawg-pcapng): blocks of (type, total length,
// body, total length again); a Section Header Block sets the byte order, Interface Description
// Blocks the link type and timestamp resolution (if_tsresol) of each interface, packets come in
// Enhanced, Simple and (obsolete) Packet Blocks; other blocks are skipped.
//
// The reader returns every record as captured, whatever its link type: Ethernet and Linux cooked
// records go to UdpExtractor (ipv4.hpp), SocketCAN records (link type 227, and CAN inside Linux
// cooked captures) to the CAN driver (specs/go1-can.md, "Recording and replay").
//
// Errors: a corrupt header (bad magic, a capture length above kMaxCaptureBytes, a bad block
// length) throws common::FileError naming the file, the byte offset and what is wrong; the records
// before it have been delivered. A file that ends inside a record is not an error: a killed
// capture is normal. The stream ends cleanly and truncated() says so.
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

// One captured packet. `data` points into the reader's buffer (or the caller's memory) and stays
// valid until the next call to PcapReader::Next.
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

    // Opens a .pcap/.pcapng file, gzip-compressed or not (zlib reads plain files transparently),
    // and reads the file header. Throws common::FileError naming the file when it cannot be
    // opened or its header is not a pcap/pcapng header.
    explicit PcapReader(const std::filesystem::path& path);
    // Reads from memory the caller keeps alive (not gzip); `name` is used in error messages.
    static PcapReader FromMemory(std::string name, std::span<const uint8_t> bytes);
    static PcapReader FromMemory(std::string name, std::string_view bytes);

    PcapReader(PcapReader&&) noexcept;
    PcapReader& operator=(PcapReader&&) noexcept;
    ~PcapReader();

    // The next record, or false at the end of the file (also when the file ends inside a record:
    // see truncated()). Throws common::FileError on a corrupt header. Does not allocate.
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
