// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/net/ipv4.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <map>

#include "algorithms/common/status.hpp"
#include "drivers/net/byte_order.hpp"

namespace bimslam::net {
namespace {
using detail::Be16;
using detail::Be32;

// The largest IPv4 datagram is 65535 bytes with its header of at least 20 bytes.
constexpr uint32_t kMaxIpPayload = 65535 - 20;
constexpr size_t kSlotBytes = 65536;
constexpr size_t kSlotBlocks = kSlotBytes / 8;  // fragment offsets count 8-byte blocks

constexpr uint16_t kEtherTypeIpv6 = 0x86DD;

// The bits [first, last) of a bitmap, word by word: a 1480-byte fragment spans 185 blocks.
template <typename F>
void ForBitRange(uint32_t first, uint32_t last, F&& f) {
    if (first >= last) return;
    const uint32_t first_word = first / 64;
    const uint32_t last_word = (last - 1) / 64;
    for (uint32_t w = first_word; w <= last_word; ++w) {
        uint64_t mask = ~uint64_t{0};
        if (w == first_word) mask &= ~uint64_t{0} << (first % 64);
        if (w == last_word) mask &= ~uint64_t{0} >> (63 - (last - 1) % 64);
        f(w, mask);
    }
}

bool IsVlanTag(uint16_t type) {
    return type == kEtherTypeVlan || type == kEtherTypeQinQ || type == kEtherTypeQinQOld;
}

}  // namespace

std::optional<uint32_t> ParseIpv4(std::string_view dotted) {
    char text[INET_ADDRSTRLEN] = {};
    if (dotted.size() >= sizeof(text)) return std::nullopt;
    std::memcpy(text, dotted.data(), dotted.size());
    in_addr address{};
    if (inet_pton(AF_INET, text, &address) != 1) return std::nullopt;
    return ntohl(address.s_addr);
}

std::string Ipv4ToString(uint32_t address) {
    return std::to_string(address >> 24) + "." + std::to_string((address >> 16) & 0xFF) + "." +
           std::to_string((address >> 8) & 0xFF) + "." + std::to_string(address & 0xFF);
}

uint16_t InternetChecksum(std::span<const uint8_t> bytes, uint32_t sum) {
    // 32-bit big-endian words into a 64-bit accumulator; folding afterwards gives the same
    // one's-complement sum as adding 16-bit words (2^16 = 1 modulo 2^16 - 1), RFC 1071 section 2.
    uint64_t acc = sum;
    const uint8_t* p = bytes.data();
    const size_t n = bytes.size();
    size_t i = 0;
    for (; i + 4 <= n; i += 4) acc += Be32(p + i);
    if (i + 2 <= n) {
        acc += Be16(p + i);
        i += 2;
    }
    if (i < n) acc += uint32_t{p[i]} << 8;
    while (acc >> 16) acc = (acc & 0xFFFF) + (acc >> 16);
    return static_cast<uint16_t>(~acc & 0xFFFF);
}

LinkResult ParseLinkLayer(uint32_t link_type, std::span<const uint8_t> frame, LinkPayload& out) {
    const uint8_t* p = frame.data();
    const size_t n = frame.size();
    size_t header = 0;
    uint16_t type = 0;
    bool may_have_tags = false;
    switch (link_type) {
        case kLinkTypeEthernet:
            // destination MAC, source MAC, EtherType (IEEE 802.3).
            if (n < 14) return LinkResult::kTruncated;
            type = Be16(p + 12);
            header = 14;
            may_have_tags = true;
            break;
        case kLinkTypeLinuxSll:
            // packet type, ARPHRD type, address length, 8 address bytes, protocol
            // (https://www.tcpdump.org/linktypes/LINKTYPE_LINUX_SLL.html).
            if (n < 16) return LinkResult::kTruncated;
            type = Be16(p + 14);
            header = 16;
            may_have_tags = true;
            break;
        case kLinkTypeLinuxSll2:
            // protocol, reserved, interface index, ARPHRD type, packet type, address length,
            // 8 address bytes (https://www.tcpdump.org/linktypes/LINKTYPE_LINUX_SLL2.html).
            if (n < 20) return LinkResult::kTruncated;
            type = Be16(p);
            header = 20;
            may_have_tags = true;
            break;
        case kLinkTypeRaw:
            // IPv4 or IPv6, told apart by the version nibble.
            if (n < 1) return LinkResult::kTruncated;
            type = (p[0] >> 4) == 4 ? kEtherTypeIpv4 : (p[0] >> 4) == 6 ? kEtherTypeIpv6 : 0;
            break;
        case kLinkTypeIpv4:
            type = kEtherTypeIpv4;
            break;
        case kLinkTypeNull:
        case kLinkTypeLoop: {
            // A 4-byte address family: host order of the capturing machine (NULL) or big-endian
            // (LOOP). AF_INET is 2 everywhere.
            if (n < 4) return LinkResult::kTruncated;
            const uint32_t be = Be32(p);
            const bool inet = be == 2 || (link_type == kLinkTypeNull && be == 0x02000000);
            type = inet ? kEtherTypeIpv4 : 0;
            header = 4;
            break;
        }
        default:
            return LinkResult::kUnsupportedLinkType;
    }
    int tags = 0;
    if (may_have_tags) {
        // 802.1Q / 802.1ad tags, possibly stacked: TCI then the next EtherType.
        while (IsVlanTag(type)) {
            if (n < header + 4) return LinkResult::kTruncated;
            type = Be16(p + header + 2);
            header += 4;
            ++tags;
        }
        // Values below 0x0600 are IEEE 802.3 lengths (LLC follows), not EtherTypes.
        if (link_type == kLinkTypeEthernet && type < 0x0600) type = 0;
    }
    out.ether_type = type;
    out.bytes = frame.subspan(header);
    out.vlan_tags = tags;
    return LinkResult::kOk;
}

std::string DescribeDrops(const ExtractorStats& s, bool bad_checksum_dropped) {
    const std::pair<const char*, uint64_t> causes[] = {
        {"of an unsupported link type", s.unsupported_link_type},
        {"cut inside the link header", s.link_truncated},
        {"not IPv4", s.not_ipv4},
        {"IPv4 but not UDP", s.not_udp},
        {"malformed IPv4", s.ip_malformed},
        {"cut short by the snap length", s.ip_truncated},
        {"with a bad IPv4 header checksum", bad_checksum_dropped ? s.ip_bad_checksum : 0},
        {"with a bad UDP length", s.udp_bad_length},
        {"with a bad UDP checksum", s.udp_bad_checksum},
        {"of incomplete IPv4 fragments", s.timed_out_datagrams + s.incomplete_at_end +
                                             s.evicted_datagrams_limit + s.evicted_datagrams_bytes +
                                             s.overlapping_datagrams + s.oversize_datagrams},
    };
    uint64_t total = 0;
    std::string detail;
    for (const auto& [what, n] : causes) {
        if (n == 0) continue;
        total += n;
        detail += (detail.empty() ? "" : ", ") + std::to_string(n) + " " + what;
    }
    if (total == 0) return "";
    return std::to_string(total) + " dropped: " + detail;
}

void ExtractorConfig::Validate() const {
    using common::Error;
    using common::StatusCode;
    if (reassembly_timeout.ns <= 0) {
        throw Error(StatusCode::kInvalidArgument,
                    "reassembly_timeout: " + std::to_string(reassembly_timeout.ns) +
                        " ns, must be positive");
    }
    if (max_datagrams_in_flight < 1 || max_datagrams_in_flight > 4096) {
        throw Error(StatusCode::kInvalidArgument,
                    "max_datagrams_in_flight: " + std::to_string(max_datagrams_in_flight) +
                        ", must be in [1, 4096]");
    }
    if (max_bytes_in_flight < 65535) {
        throw Error(StatusCode::kInvalidArgument,
                    "max_bytes_in_flight: " + std::to_string(max_bytes_in_flight) +
                        ", must be at least 65535 (one largest datagram)");
    }
}

UdpExtractor::UdpExtractor(const ExtractorConfig& config) : config_(config) {
    config_.Validate();
    slots_.resize(config_.max_datagrams_in_flight);
    for (Slot& slot : slots_) {
        slot.payload.resize(kSlotBytes);
        slot.have.resize(kSlotBlocks / 64);
    }
}

size_t UdpExtractor::datagrams_in_flight() const { return in_flight_; }

bool UdpExtractor::Feed(const PcapRecord& record, UdpDatagram& out) {
    return FeedFrame(record.link_type, record.timestamp_ns, record.data, record.index, out);
}

bool UdpExtractor::FeedFrame(uint32_t link_type, int64_t timestamp_ns,
                             std::span<const uint8_t> frame, uint64_t record_index,
                             UdpDatagram& out) {
    ++stats_.records;
    if (in_flight_ > 0) Expire(timestamp_ns);
    LinkPayload link;
    switch (ParseLinkLayer(link_type, frame, link)) {
        case LinkResult::kOk:
            break;
        case LinkResult::kUnsupportedLinkType:
            ++stats_.unsupported_link_type;
            return false;
        case LinkResult::kTruncated:
            ++stats_.link_truncated;
            return false;
    }
    if (link.vlan_tags > 0) ++stats_.vlan_tagged;
    if (link.ether_type != kEtherTypeIpv4) {
        ++stats_.not_ipv4;
        return false;
    }
    return Ipv4(timestamp_ns, link.bytes, record_index, out);
}

bool UdpExtractor::FeedIpv4(int64_t timestamp_ns, std::span<const uint8_t> packet,
                            uint64_t record_index, UdpDatagram& out) {
    ++stats_.records;
    if (in_flight_ > 0) Expire(timestamp_ns);
    return Ipv4(timestamp_ns, packet, record_index, out);
}

bool UdpExtractor::Ipv4(int64_t timestamp_ns, std::span<const uint8_t> packet,
                        uint64_t record_index, UdpDatagram& out) {
    // RFC 791, section 3.1.
    const uint8_t* p = packet.data();
    if (packet.size() < 20) {
        if (!packet.empty() && (p[0] >> 4) != 4) {
            ++stats_.ip_malformed;
        } else {
            ++stats_.ip_truncated;
        }
        return false;
    }
    const size_t header = size_t{p[0] & 0x0Fu} * 4;
    if ((p[0] >> 4) != 4 || header < 20) {
        ++stats_.ip_malformed;
        return false;
    }
    if (packet.size() < header) {
        ++stats_.ip_truncated;
        return false;
    }
    const size_t total = Be16(p + 2);
    if (total < header) {
        ++stats_.ip_malformed;
        return false;
    }
    if (total > packet.size()) {
        ++stats_.ip_truncated;
        return false;
    }
    if (InternetChecksum(packet.first(header)) != 0) {
        ++stats_.ip_bad_checksum;
        if (config_.drop_bad_ip_checksum) return false;
    }
    const uint8_t protocol = p[9];
    if (protocol != kIpProtocolUdp) {
        ++stats_.not_udp;
        return false;
    }
    // Link-layer padding and trailers (Ethernet minimum frame, FCS) follow the total length.
    const std::span<const uint8_t> payload = packet.subspan(header, total - header);
    const uint32_t src = Be32(p + 12);
    const uint32_t dst = Be32(p + 16);
    const uint16_t flags_offset = Be16(p + 6);
    const bool more = (flags_offset & 0x2000) != 0;
    const uint32_t offset = uint32_t{flags_offset & 0x1FFFu} * 8;
    if (!more && offset == 0) {
        return DeliverUdp(timestamp_ns, src, dst, payload, record_index, 1, out);
    }
    std::span<const uint8_t> datagram;
    uint32_t fragments = 0;
    if (!Reassemble(timestamp_ns, src, dst, Be16(p + 4), protocol, offset, more, payload, datagram,
                    fragments)) {
        return false;
    }
    ++stats_.reassembled;
    return DeliverUdp(timestamp_ns, src, dst, datagram, record_index, fragments, out);
}

bool UdpExtractor::DeliverUdp(int64_t timestamp_ns, uint32_t src, uint32_t dst,
                              std::span<const uint8_t> ip_payload, uint64_t record_index,
                              uint32_t fragments, UdpDatagram& out) {
    // RFC 768: source port, destination port, length (header included), checksum.
    if (ip_payload.size() < 8) {
        ++stats_.udp_bad_length;
        return false;
    }
    const uint8_t* u = ip_payload.data();
    const size_t length = Be16(u + 4);
    if (length < 8 || length > ip_payload.size()) {
        ++stats_.udp_bad_length;
        return false;
    }
    if (config_.check_udp_checksum && Be16(u + 6) != 0) {
        // Pseudo-header: source, destination, zero, protocol, UDP length.
        const uint32_t pseudo = (src >> 16) + (src & 0xFFFF) + (dst >> 16) + (dst & 0xFFFF) +
                                kIpProtocolUdp + static_cast<uint32_t>(length);
        if (InternetChecksum(ip_payload.first(length), pseudo) != 0) {
            ++stats_.udp_bad_checksum;
            return false;
        }
    }
    out.timestamp_ns = timestamp_ns;
    out.src_ip = src;
    out.dst_ip = dst;
    out.src_port = Be16(u);
    out.dst_port = Be16(u + 2);
    out.payload = ip_payload.subspan(8, length - 8);
    out.record_index = record_index;
    out.fragments = fragments;
    ++stats_.datagrams;
    return true;
}

UdpExtractor::Slot* UdpExtractor::OldestSlot() {
    Slot* oldest = nullptr;
    for (Slot& slot : slots_) {
        if (slot.used && (oldest == nullptr || slot.first_ns < oldest->first_ns)) oldest = &slot;
    }
    return oldest;
}

void UdpExtractor::Drop(Slot& slot) {
    bytes_in_flight_ -= slot.received;
    --in_flight_;
    slot.used = false;
}

void UdpExtractor::Expire(int64_t now_ns) {
    for (Slot& slot : slots_) {
        // Unsigned difference: capture times may be anything (pcapng offsets), and a clock that
        // went backwards expires nothing.
        if (slot.used && now_ns > slot.first_ns &&
            static_cast<uint64_t>(now_ns) - static_cast<uint64_t>(slot.first_ns) >
                static_cast<uint64_t>(config_.reassembly_timeout.ns)) {
            ++stats_.timed_out_datagrams;
            Drop(slot);
        }
    }
}

void UdpExtractor::Finish() {
    for (Slot& slot : slots_) {
        if (slot.used) {
            ++stats_.incomplete_at_end;
            Drop(slot);
        }
    }
}

bool UdpExtractor::Reassemble(int64_t timestamp_ns, uint32_t src, uint32_t dst, uint16_t id,
                              uint8_t protocol, uint32_t offset, bool more,
                              std::span<const uint8_t> fragment, std::span<const uint8_t>& datagram,
                              uint32_t& fragments) {
    const uint32_t length = static_cast<uint32_t>(fragment.size());
    const uint32_t end = offset + length;
    Slot* slot = nullptr;
    for (Slot& s : slots_) {
        if (s.used && s.src == src && s.dst == dst && s.id == id && s.protocol == protocol) {
            slot = &s;
            break;
        }
    }
    // Every fragment but the last carries a multiple of 8 bytes (offsets count 8-byte blocks).
    if (more && (length == 0 || length % 8 != 0)) {
        ++stats_.ip_malformed;
        return false;
    }
    if (end > kMaxIpPayload) {
        ++stats_.oversize_datagrams;
        if (slot != nullptr) Drop(*slot);
        return false;
    }
    if (slot == nullptr) {
        if (in_flight_ == slots_.size()) {
            ++stats_.evicted_datagrams_limit;
            Drop(*OldestSlot());
        }
        for (Slot& s : slots_) {
            if (!s.used) {
                slot = &s;
                break;
            }
        }
        slot->used = true;
        slot->src = src;
        slot->dst = dst;
        slot->id = id;
        slot->protocol = protocol;
        slot->first_ns = timestamp_ns;
        slot->total = 0;
        slot->received = 0;
        slot->max_end = 0;
        slot->fragments = 0;
        std::fill(slot->have.begin(), slot->have.end(), uint64_t{0});
        ++in_flight_;
    }
    // The last fragment fixes the length; data beyond it, or a second different end, make the
    // datagram inconsistent (ip_frag_queue in net/ipv4/ip_fragment.c discards the queue too).
    const bool have_last = slot->total != 0;
    if ((have_last && (end > slot->total || (!more && end != slot->total))) ||
        (!more && end < slot->max_end)) {
        ++stats_.overlapping_datagrams;
        Drop(*slot);
        return false;
    }
    // Blocks [first, last) of this fragment: none held yet (new), all (duplicate), some (overlap).
    const uint32_t first_block = offset / 8;
    const uint32_t last_block = (end + 7) / 8;
    uint32_t held = 0;
    ForBitRange(first_block, last_block, [&](uint32_t w, uint64_t mask) {
        held += static_cast<uint32_t>(std::popcount(slot->have[w] & mask));
    });
    if (length > 0 && held == last_block - first_block) {
        ++stats_.duplicate_fragments;
        return false;
    }
    if (held != 0) {
        ++stats_.overlapping_datagrams;
        Drop(*slot);
        return false;
    }
    // Memory: give up the oldest other datagrams until this fragment fits.
    while (bytes_in_flight_ + length > config_.max_bytes_in_flight) {
        Slot* oldest = nullptr;
        for (Slot& s : slots_) {
            if (s.used && &s != slot && (oldest == nullptr || s.first_ns < oldest->first_ns)) {
                oldest = &s;
            }
        }
        if (oldest == nullptr) break;  // cannot happen: one datagram is <= 65515 bytes
        ++stats_.evicted_datagrams_bytes;
        Drop(*oldest);
    }
    if (length > 0) std::memcpy(slot->payload.data() + offset, fragment.data(), length);
    ForBitRange(first_block, last_block, [&](uint32_t w, uint64_t mask) { slot->have[w] |= mask; });
    if (!more) slot->total = end;
    slot->received += length;
    slot->max_end = std::max(slot->max_end, end);
    bytes_in_flight_ += length;
    ++slot->fragments;
    ++stats_.fragments;
    if (slot->total == 0 || slot->received != slot->total) return false;
    // Complete: the buffer keeps its bytes until the slot is reused, after the caller's next Feed.
    datagram = std::span<const uint8_t>(slot->payload.data(), slot->total);
    fragments = slot->fragments;
    Drop(*slot);
    return true;
}

PortGuess GuessPorts(std::span<const UdpDatagram> datagrams, size_t lidar_payload_bytes,
                     size_t imu_payload_bytes) {
    std::map<uint16_t, std::pair<uint64_t, uint64_t>> counts;  // port -> (lidar, imu) sized
    PortGuess guess;
    for (const UdpDatagram& d : datagrams) {
        ++guess.datagrams;
        auto& c = counts[d.dst_port];
        if (lidar_payload_bytes != 0 && d.payload.size() == lidar_payload_bytes) ++c.first;
        if (imu_payload_bytes != 0 && d.payload.size() == imu_payload_bytes) ++c.second;
    }
    for (const auto& [port, c] : counts) {  // ascending ports: ties keep the lower one
        if (c.first > guess.lidar_datagrams) {
            guess.lidar_port = port;
            guess.lidar_datagrams = c.first;
        }
    }
    for (const auto& [port, c] : counts) {
        if (guess.lidar_port == port) continue;
        if (c.second > guess.imu_datagrams) {
            guess.imu_port = port;
            guess.imu_datagrams = c.second;
        }
    }
    return guess;
}

PortGuess GuessPortsInCapture(const std::filesystem::path& path, size_t lidar_payload_bytes,
                              size_t imu_payload_bytes, size_t max_datagrams) {
    PcapReader reader(path);
    UdpExtractor extractor;
    std::vector<UdpDatagram> datagrams;
    PcapRecord record;
    UdpDatagram datagram;
    while (datagrams.size() < max_datagrams && reader.Next(record)) {
        if (extractor.Feed(record, datagram)) {
            datagrams.push_back(datagram);  // GuessPorts reads the payload size only
        }
    }
    PortGuess guess = GuessPorts(datagrams, lidar_payload_bytes, imu_payload_bytes);
    guess.records = reader.records();
    guess.extractor = extractor.stats();
    return guess;
}

}  // namespace bimslam::net
