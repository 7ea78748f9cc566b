// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// From captured link-layer frames to UDP datagrams: link layers (Ethernet with 802.1Q/802.1ad
// tags, Linux cooked SLL and SLL2, raw IPv4, BSD loopback), IPv4 with fragment reassembly, UDP.
//
// Real Ouster sensors on a 1500-byte MTU send every lidar packet as IPv4 fragments and libpcap
// does not reassemble them (specs/ouster-lidar.md, "Capture files"), so UdpExtractor does, the way
// the Linux receive path does (net/ipv4/ip_fragment.c, net/ipv4/inet_fragment.c): fragments are
// keyed by (source, destination, identification, protocol), may come in any order, exact or
// contained duplicates are ignored, any other overlap discards the whole datagram (RFC 5722 rule,
// which Linux applies to IPv4 too since 2018), and incomplete datagrams expire after a timeout.
//
// Per record: no allocation (reassembly buffers are allocated by the constructor), no exceptions;
// every drop is counted in ExtractorStats.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/common/time.hpp"
#include "drivers/net/pcap_reader.hpp"

namespace bimslam::net {

// IPv4 addresses are uint32_t in host byte order: 127.0.0.1 is 0x7F000001.
std::optional<uint32_t> ParseIpv4(std::string_view dotted);
std::string Ipv4ToString(uint32_t address);

// The Internet checksum (RFC 1071) of `bytes` added to `sum` (the partial sum of a pseudo-header,
// or 0), folded and complemented. A header whose checksum field is included checks to 0.
uint16_t InternetChecksum(std::span<const uint8_t> bytes, uint32_t sum = 0);

inline constexpr uint16_t kEtherTypeIpv4 = 0x0800;
inline constexpr uint16_t kEtherTypeVlan = 0x8100;     // 802.1Q customer tag
inline constexpr uint16_t kEtherTypeQinQ = 0x88A8;     // 802.1ad service tag
inline constexpr uint16_t kEtherTypeQinQOld = 0x9100;  // pre-standard stacked tag
inline constexpr uint8_t kIpProtocolUdp = 17;

// The network-layer packet inside a link-layer frame.
struct LinkPayload {
    uint16_t ether_type = 0;  // EtherType (or the SLL protocol field): 0x0800 for IPv4
    std::span<const uint8_t> bytes;
    int vlan_tags = 0;  // 802.1Q/802.1ad tags removed
};
enum class LinkResult : uint8_t {
    kOk,
    kUnsupportedLinkType,  // CAN, IEEE 802.11, ...: not parsed here
    kTruncated,            // the frame is shorter than its link-layer header
};
// Ethernet (1), Linux SLL (113) and SLL2 (276), raw (101; IPv4 only), IPv4 (228), BSD loopback
// (0, 108). VLAN tags are removed after Ethernet and SLL headers alike (tcpdump -i any captures
// may keep them). An IEEE 802.3 length field in place of an EtherType gives ether_type 0.
LinkResult ParseLinkLayer(uint32_t link_type, std::span<const uint8_t> frame, LinkPayload& out);

// One UDP datagram. `payload` points into the record, or into the extractor's reassembly buffer,
// and stays valid until the next call to UdpExtractor::Feed (UdpSource: until the next Receive).
struct UdpDatagram {
    int64_t timestamp_ns = 0;  // capture (or kernel receive) time of the packet that completed it
    uint32_t src_ip = 0;
    uint32_t dst_ip = 0;
    uint16_t src_port = 0;
    uint16_t dst_port = 0;
    std::span<const uint8_t> payload;
    uint64_t record_index = 0;  // pcap record that completed it
    uint32_t fragments = 1;     // IPv4 fragments it was reassembled from (1: not fragmented)
};

struct ExtractorConfig {
    // Capture time after a datagram's first fragment at which it is given up (Linux's
    // ipfrag_time is 30 s; sensors send all fragments within microseconds).
    common::Duration reassembly_timeout = common::Duration::FromMilliseconds(1000);
    // Datagrams in reassembly at once; each owns a 64 KiB buffer allocated by the constructor.
    size_t max_datagrams_in_flight = 16;
    // Fragment bytes held in reassembly at once (Linux: ipfrag_high_thresh, 4 MiB). At least
    // 65535, the largest datagram.
    size_t max_bytes_in_flight = 1 << 20;
    // A wrong IPv4 header checksum is counted (ip_bad_checksum) and the packet kept, as
    // Wireshark and the Ouster SDK do by default: real recordings carry bad checksums (addresses
    // rewritten after capture, checksum offload on the capturing host), and dropping them made
    // such a capture read as "0 UDP datagrams". The fields are still checked for consistency
    // (lengths, offsets), and the Ouster packets carry their own checks (size, CRC-64). True
    // drops them, as the kernel does.
    bool drop_bad_ip_checksum = false;
    // UDP checksums in captures taken on the sending host are often wrong (checksum offload
    // fills them in after capture), so they are not checked unless asked; when checked, a
    // non-zero wrong checksum drops the datagram (0 means "not computed", RFC 768).
    bool check_udp_checksum = false;

    // Throws common::Error (kInvalidArgument) naming the field.
    void Validate() const;
};

struct ExtractorStats {
    uint64_t records = 0;                // records fed
    uint64_t unsupported_link_type = 0;  // e.g. SocketCAN (227): not IP at all
    uint64_t link_truncated = 0;         // shorter than the link-layer header
    uint64_t not_ipv4 = 0;               // ARP, IPv6, LLC, CAN in SLL, ...
    uint64_t vlan_tagged = 0;            // frames that carried 802.1Q/802.1ad tags
    uint64_t not_udp = 0;                // IPv4 of another protocol (TCP, ICMP, ...)
    uint64_t ip_malformed = 0;      // version, header length, total length < header, bad offsets
    uint64_t ip_truncated = 0;      // captured bytes fewer than the IPv4 total length (snaplen)
    uint64_t ip_bad_checksum = 0;   // counted; dropped only when drop_bad_ip_checksum
    uint64_t udp_bad_length = 0;    // UDP length < 8 or beyond the IP payload
    uint64_t udp_bad_checksum = 0;  // only with check_udp_checksum; dropped
    uint64_t datagrams = 0;         // datagrams returned (unfragmented and reassembled)
    // Reassembly.
    uint64_t fragments = 0;                // fragments accepted into reassembly
    uint64_t reassembled = 0;              // datagrams completed from fragments
    uint64_t duplicate_fragments = 0;      // contained in what was already there; ignored
    uint64_t overlapping_datagrams = 0;    // dropped: fragments overlapped or disagreed on the end
    uint64_t oversize_datagrams = 0;       // dropped: offset + length beyond 65535
    uint64_t timed_out_datagrams = 0;      // dropped: incomplete after reassembly_timeout
    uint64_t evicted_datagrams_limit = 0;  // dropped: max_datagrams_in_flight reached
    uint64_t evicted_datagrams_bytes = 0;  // dropped: max_bytes_in_flight reached
    uint64_t incomplete_at_end = 0;        // dropped by Finish(): the capture ended first
};

// "N records dropped: a not IPv4, b bad IPv4 checksum, ..." (causes with a count only), or "" when
// nothing was dropped: for messages about captures that yield fewer datagrams than expected.
std::string DescribeDrops(const ExtractorStats& stats, bool bad_checksum_dropped);

class UdpExtractor {
public:
    // Throws common::Error when the configuration is invalid. Allocates the reassembly buffers.
    explicit UdpExtractor(const ExtractorConfig& config = {});

    // Feeds one captured frame; true when it yields a datagram (a whole one, or the fragment that
    // completed one), written to `out`. Never throws, never allocates.
    bool Feed(const PcapRecord& record, UdpDatagram& out);
    bool FeedFrame(uint32_t link_type, int64_t timestamp_ns, std::span<const uint8_t> frame,
                   uint64_t record_index, UdpDatagram& out);
    // Feeds one IPv4 packet (no link layer).
    bool FeedIpv4(int64_t timestamp_ns, std::span<const uint8_t> packet, uint64_t record_index,
                  UdpDatagram& out);

    // The end of the capture: datagrams still in reassembly are dropped and counted.
    void Finish();

    const ExtractorStats& stats() const { return stats_; }
    size_t datagrams_in_flight() const;
    size_t bytes_in_flight() const { return bytes_in_flight_; }
    const ExtractorConfig& config() const { return config_; }

private:
    struct Slot {
        bool used = false;
        uint32_t src = 0;
        uint32_t dst = 0;
        uint16_t id = 0;
        uint8_t protocol = 0;
        int64_t first_ns = 0;   // capture time of the first fragment received
        uint32_t total = 0;     // payload length, known once the last fragment (MF=0) came
        uint32_t received = 0;  // payload bytes held
        uint32_t max_end = 0;   // highest fragment end seen
        uint32_t fragments = 0;
        std::vector<uint8_t> payload;  // 65536 bytes
        std::vector<uint64_t> have;    // one bit per 8-byte block of payload
    };

    bool Ipv4(int64_t timestamp_ns, std::span<const uint8_t> packet, uint64_t record_index,
              UdpDatagram& out);
    bool Reassemble(int64_t timestamp_ns, uint32_t src, uint32_t dst, uint16_t id, uint8_t protocol,
                    uint32_t offset, bool more, std::span<const uint8_t> fragment,
                    std::span<const uint8_t>& datagram, uint32_t& fragments);
    void Expire(int64_t now_ns);
    void Drop(Slot& slot);
    Slot* OldestSlot();
    bool DeliverUdp(int64_t timestamp_ns, uint32_t src, uint32_t dst,
                    std::span<const uint8_t> ip_payload, uint64_t record_index, uint32_t fragments,
                    UdpDatagram& out);

    ExtractorConfig config_;
    ExtractorStats stats_;
    std::vector<Slot> slots_;
    size_t in_flight_ = 0;
    size_t bytes_in_flight_ = 0;
};

// Guessing the sensor's ports from payload sizes when they are not known (specs/ouster-lidar.md,
// "Capture files"): the lidar port is the destination port with the most datagrams of exactly
// `lidar_payload_bytes`, the IMU port the one (another) with the most of `imu_payload_bytes`
// (0: do not guess). Ties go to the lower port.
struct PortGuess {
    std::optional<uint16_t> lidar_port;
    std::optional<uint16_t> imu_port;
    uint64_t lidar_datagrams = 0;  // datagrams of the lidar size on the chosen port
    uint64_t imu_datagrams = 0;
    uint64_t datagrams = 0;    // datagrams looked at
    uint64_t records = 0;      // capture records read (GuessPortsInCapture)
    ExtractorStats extractor;  // why records gave no datagram (GuessPortsInCapture)
};
// Only dst_port and payload.size() are read, so the payload spans may already be stale.
PortGuess GuessPorts(std::span<const UdpDatagram> datagrams, size_t lidar_payload_bytes,
                     size_t imu_payload_bytes);
// A first pass over (at most `max_datagrams` datagrams of) a capture file. Throws
// common::FileError as PcapReader does.
PortGuess GuessPortsInCapture(const std::filesystem::path& path, size_t lidar_payload_bytes,
                              size_t imu_payload_bytes, size_t max_datagrams = 4096);

}  // namespace bimslam::net
