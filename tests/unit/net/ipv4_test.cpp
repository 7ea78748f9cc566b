// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/net/ipv4.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"
#include "drivers/net/pcap_reader.hpp"
#include "drivers/net/pcap_writer.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::net {
namespace {
namespace BIMSLAM_UNITY_ID {

constexpr int64_t kIpT0 = 1'700'000'000'000'000'000;
constexpr uint32_t kSensorIp = 0x0A050501;  // 10.5.5.1
constexpr uint32_t kHostIp = 0x0A050502;

struct IpFrame {
    int64_t ts = 0;
    std::string bytes;
    uint32_t link = kLinkTypeEthernet;
};

std::vector<IpFrame> Frames(const std::string& pcap) {
    PcapReader reader = PcapReader::FromMemory("frames.pcap", pcap);
    std::vector<IpFrame> out;
    PcapRecord r;
    while (reader.Next(r)) {
        out.push_back({r.timestamp_ns,
                       std::string(reinterpret_cast<const char*>(r.data.data()), r.data.size()),
                       r.link_type});
    }
    return out;
}

std::string Capture(const std::vector<IpFrame>& frames, uint32_t link = kLinkTypeEthernet) {
    PcapWriterConfig options;
    options.link_type = link;
    PcapWriter writer(options);
    for (const IpFrame& f : frames) writer.WriteRecord(f.ts, test::AsBytes(f.bytes));
    return writer.bytes();
}

// The Ethernet frames of one datagram as the writer cuts them.
std::vector<IpFrame> UdpFrames(int64_t ts, uint16_t dst_port, const std::string& payload,
                               uint32_t mtu, uint16_t ip_id = 1) {
    PcapWriterConfig options;
    options.first_ip_id = ip_id;
    PcapWriter writer(options);
    writer.WriteUdp(ts, kSensorIp, 7502, kHostIp, dst_port, test::AsBytes(payload), mtu);
    return Frames(writer.bytes());
}

struct Got {
    int64_t ts = 0;
    uint32_t src = 0;
    uint32_t dst = 0;
    uint16_t sport = 0;
    uint16_t dport = 0;
    std::string payload;
    uint32_t fragments = 0;
    uint64_t record = 0;
};

std::vector<Got> Extract(const std::string& pcap, UdpExtractor& extractor) {
    PcapReader reader = PcapReader::FromMemory("x.pcap", pcap);
    std::vector<Got> out;
    PcapRecord r;
    UdpDatagram d;
    while (reader.Next(r)) {
        if (extractor.Feed(r, d)) {
            out.push_back(
                {d.timestamp_ns, d.src_ip, d.dst_ip, d.src_port, d.dst_port,
                 std::string(reinterpret_cast<const char*>(d.payload.data()), d.payload.size()),
                 d.fragments, d.record_index});
        }
    }
    extractor.Finish();
    return out;
}

size_t ExpectedFragments(size_t payload, uint32_t mtu) {
    const size_t ip_payload = payload + 8;
    if (mtu == 0 || ip_payload + 20 <= mtu) return 1;
    const size_t chunk = (mtu - 20) & ~size_t{7};
    return (ip_payload + chunk - 1) / chunk;
}

// Rewrites an IPv4 header field of an Ethernet frame and fixes the header checksum.
void SetBe16(std::string& frame, size_t at, uint16_t v) {
    frame[at] = static_cast<char>(v >> 8);
    frame[at + 1] = static_cast<char>(v);
}
void FixIpChecksum(std::string& frame, size_t ip = 14) {
    SetBe16(frame, ip + 10, 0);
    SetBe16(frame, ip + 10, InternetChecksum(test::AsBytes(frame).subspan(ip, 20)));
}

TEST(Ipv4, AddressesAndChecksum) {
    EXPECT_EQ(ParseIpv4("127.0.0.1"), 0x7F000001u);
    EXPECT_EQ(ParseIpv4("10.5.5.87"), 0x0A050557u);
    EXPECT_FALSE(ParseIpv4("10.5.5"));
    EXPECT_FALSE(ParseIpv4("300.1.1.1"));
    EXPECT_FALSE(ParseIpv4(std::string(40, '1')));
    EXPECT_EQ(Ipv4ToString(0xC0A80164), "192.168.1.100");
    // RFC 1071's example: 00 01 f2 03 f4 f5 f6 f7 sums to ddf2.
    const std::string bytes("\x00\x01\xf2\x03\xf4\xf5\xf6\xf7", 8);
    EXPECT_EQ(InternetChecksum(test::AsBytes(bytes)), static_cast<uint16_t>(~0xddf2));
    EXPECT_EQ(InternetChecksum(test::AsBytes(bytes).first(7)),
              InternetChecksum(test::AsBytes(std::string("\x00\x01\xf2\x03\xf4\xf5\xf6\x00", 8))));
}

TEST(UdpExtractor, RoundTripBitIdenticalWithFragmentation) {
    std::mt19937 rng(5);
    for (const uint32_t mtu : {0u, 1500u, 576u}) {
        for (const bool ns : {true, false}) {
            PcapWriterConfig options;
            options.nanosecond = ns;
            PcapWriter writer(options);
            std::vector<std::string> payloads;
            for (size_t size : {0, 1, 6464, 1472, 1473, 1464, 65507, 48, 24832}) {
                payloads.push_back(test::RandomBytes(size, rng));
            }
            for (int i = 0; i < 40; ++i) {
                const size_t size = i % 2 ? rng() % 9000 : rng() % 65508;
                payloads.push_back(test::RandomBytes(size, rng));
            }
            for (size_t i = 0; i < payloads.size(); ++i) {
                writer.WriteUdp(kIpT0 + static_cast<int64_t>(i) * 100'000'123, kSensorIp,
                                static_cast<uint16_t>(7000 + i), kHostIp,
                                static_cast<uint16_t>(8000 + i), test::AsBytes(payloads[i]), mtu);
            }
            ExtractorConfig config;
            config.check_udp_checksum = true;
            UdpExtractor extractor(config);
            const auto got = Extract(writer.bytes(), extractor);
            ASSERT_EQ(got.size(), payloads.size()) << "mtu " << mtu;
            size_t fragments = 0;
            for (size_t i = 0; i < payloads.size(); ++i) {
                const int64_t ts = kIpT0 + static_cast<int64_t>(i) * 100'000'123;
                ASSERT_EQ(got[i].payload, payloads[i]) << "mtu " << mtu << " datagram " << i;
                EXPECT_EQ(got[i].ts, ns ? ts : ts / 1000 * 1000);
                EXPECT_EQ(got[i].src, kSensorIp);
                EXPECT_EQ(got[i].dst, kHostIp);
                EXPECT_EQ(got[i].sport, 7000 + i);
                EXPECT_EQ(got[i].dport, 8000 + i);
                EXPECT_EQ(got[i].fragments, ExpectedFragments(payloads[i].size(), mtu));
                fragments += got[i].fragments > 1 ? got[i].fragments : 0;
            }
            const ExtractorStats& s = extractor.stats();
            EXPECT_EQ(s.datagrams, payloads.size());
            EXPECT_EQ(s.fragments, fragments);
            EXPECT_EQ(s.udp_bad_checksum, 0u);
            EXPECT_EQ(s.ip_bad_checksum, 0u);
            EXPECT_EQ(s.incomplete_at_end, 0u);
            EXPECT_EQ(extractor.datagrams_in_flight(), 0u);
            EXPECT_EQ(extractor.bytes_in_flight(), 0u);
        }
    }
}

TEST(UdpExtractor, ShuffledAndDuplicatedFragments) {
    std::mt19937 rng(6);
    struct Item {
        double key;
        IpFrame frame;
    };
    std::vector<std::string> payloads;
    std::vector<std::vector<IpFrame>> datagrams;
    for (int d = 0; d < 30; ++d) {
        payloads.push_back(test::RandomBytes(2000 + rng() % 30000, rng));
        datagrams.push_back(UdpFrames(kIpT0, static_cast<uint16_t>(10000 + d), payloads.back(),
                                      1500, static_cast<uint16_t>(100 + d)));
    }
    // Every fragment gets a random position; a duplicate goes somewhere after its original but
    // before the fragment that completes its datagram (later it would start a new datagram).
    std::vector<Item> items;
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<double> completes(datagrams.size(), 0.0);
    for (size_t d = 0; d < datagrams.size(); ++d) {
        for (const IpFrame& f : datagrams[d]) {
            items.push_back({u(rng), f});
            completes[d] = std::max(completes[d], items.back().key);
        }
    }
    size_t duplicates = 0;
    const size_t originals = items.size();
    size_t at = 0;
    for (size_t d = 0; d < datagrams.size(); ++d) {
        for (size_t f = 0; f < datagrams[d].size(); ++f, ++at) {
            const double key = items[at].key;
            if (key < completes[d] && u(rng) < 0.3) {
                items.push_back(
                    {key + (completes[d] - key) * (0.01 + 0.98 * u(rng)), items[at].frame});
                ++duplicates;
            }
        }
    }
    ASSERT_GT(duplicates, 10u);
    ASSERT_EQ(at, originals);
    std::sort(items.begin(), items.end(),
              [](const Item& a, const Item& b) { return a.key < b.key; });
    std::vector<IpFrame> frames;
    for (size_t i = 0; i < items.size(); ++i) {
        frames.push_back(items[i].frame);
        frames.back().ts = kIpT0 + static_cast<int64_t>(i) * 1000;
    }
    ExtractorConfig config;
    config.max_datagrams_in_flight = 64;
    config.max_bytes_in_flight = 4 << 20;
    UdpExtractor extractor(config);
    const auto got = Extract(Capture(frames), extractor);
    ASSERT_EQ(got.size(), payloads.size());
    std::map<uint16_t, std::string> by_port;
    for (const Got& g : got) by_port[g.dport] = g.payload;
    for (size_t d = 0; d < payloads.size(); ++d) {
        EXPECT_EQ(by_port[static_cast<uint16_t>(10000 + d)], payloads[d]) << d;
    }
    EXPECT_EQ(extractor.stats().duplicate_fragments, duplicates);
    EXPECT_EQ(extractor.stats().overlapping_datagrams, 0u);
    EXPECT_EQ(extractor.stats().incomplete_at_end, 0u);
    EXPECT_EQ(extractor.stats().reassembled, payloads.size());
}

TEST(UdpExtractor, MissingFragmentTimesOut) {
    std::mt19937 rng(7);
    std::vector<IpFrame> frames;
    std::vector<std::string> payloads;
    for (int d = 0; d < 5; ++d) {
        payloads.push_back(test::RandomBytes(6464, rng));
        auto f = UdpFrames(kIpT0 + d * 400'000'000, static_cast<uint16_t>(7502), payloads.back(),
                           1500, static_cast<uint16_t>(d + 1));
        ASSERT_EQ(f.size(), 5u);
        if (d == 1) f.erase(f.begin() + 2);  // lost on the wire
        frames.insert(frames.end(), f.begin(), f.end());
    }
    ExtractorConfig config;  // 1 s timeout: datagram 1 (0.4 s) expires at datagram 4 (1.6 s)
    UdpExtractor extractor(config);
    const auto got = Extract(Capture(frames), extractor);
    ASSERT_EQ(got.size(), 4u);
    EXPECT_EQ(got[0].payload, payloads[0]);
    EXPECT_EQ(got[1].payload, payloads[2]);
    EXPECT_EQ(got[3].payload, payloads[4]);
    EXPECT_EQ(extractor.stats().timed_out_datagrams, 1u);
    EXPECT_EQ(extractor.stats().incomplete_at_end, 0u);

    // Missing in the last datagram: nothing later expires it; Finish() counts it.
    frames.erase(frames.end() - 1);
    UdpExtractor at_end(config);
    EXPECT_EQ(Extract(Capture(frames), at_end).size(), 3u);
    EXPECT_EQ(at_end.stats().timed_out_datagrams, 1u);
    EXPECT_EQ(at_end.stats().incomplete_at_end, 1u);
    EXPECT_EQ(at_end.datagrams_in_flight(), 0u);
    EXPECT_EQ(at_end.bytes_in_flight(), 0u);

    // Fragments of one datagram 2 s apart: the first part expires, the rest starts anew.
    auto slow = UdpFrames(kIpT0, 7502, payloads[0], 1500);
    slow[3].ts = slow[4].ts = kIpT0 + 2'000'000'000;
    UdpExtractor late(config);
    EXPECT_TRUE(Extract(Capture(slow), late).empty());
    EXPECT_EQ(late.stats().timed_out_datagrams, 1u);
    EXPECT_EQ(late.stats().incomplete_at_end, 1u);
}

TEST(UdpExtractor, OverlapsAndInconsistentEndsDropTheDatagram) {
    std::mt19937 rng(8);
    const std::string payload = test::RandomBytes(6464, rng);
    const auto f = UdpFrames(kIpT0, 7502, payload, 1500);
    ASSERT_EQ(f.size(), 5u);
    // Fragment 1 again, but starting 8 bytes earlier: overlaps fragment 0.
    IpFrame shifted = f[1];
    SetBe16(shifted.bytes, 14 + 6, 0x2000 | (1480 / 8 - 1));
    FixIpChecksum(shifted.bytes);
    UdpExtractor extractor;
    EXPECT_TRUE(Extract(Capture({f[0], shifted, f[1], f[2], f[3], f[4]}), extractor).empty());
    EXPECT_EQ(extractor.stats().overlapping_datagrams, 1u);
    EXPECT_EQ(extractor.stats().incomplete_at_end, 1u);  // fragments 1-4 started a new one

    // A second last fragment with another end.
    IpFrame other_end = f[4];
    other_end.bytes.resize(other_end.bytes.size() - 8);
    SetBe16(other_end.bytes, 14 + 2, static_cast<uint16_t>(other_end.bytes.size() - 14));
    FixIpChecksum(other_end.bytes);
    UdpExtractor ends;
    EXPECT_TRUE(Extract(Capture({f[4], f[0], other_end, f[1], f[2], f[3]}), ends).empty());
    EXPECT_EQ(ends.stats().overlapping_datagrams, 1u);
    // Data beyond the end a last fragment set.
    UdpExtractor beyond;
    EXPECT_TRUE(Extract(Capture({other_end, f[4]}), beyond).empty());
    EXPECT_EQ(beyond.stats().overlapping_datagrams, 1u);

    // Exact and contained duplicates are ignored.
    UdpExtractor dup;
    const auto got = Extract(Capture({f[0], f[0], f[2], f[1], f[2], f[4], f[4], f[3]}), dup);
    ASSERT_EQ(got.size(), 1u);
    EXPECT_EQ(got[0].payload, payload);
    EXPECT_EQ(got[0].fragments, 5u);
    EXPECT_EQ(dup.stats().duplicate_fragments, 3u);
}

TEST(UdpExtractor, OversizeAndMalformedFragments) {
    std::mt19937 rng(9);
    const auto f = UdpFrames(kIpT0, 7502, test::RandomBytes(3000, rng), 1500);
    IpFrame far = f[2];  // last fragment moved to offset 65512: ends beyond 65515
    SetBe16(far.bytes, 14 + 6, 65512 / 8);
    FixIpChecksum(far.bytes);
    IpFrame odd = f[1];  // a middle fragment whose length is not a multiple of 8
    odd.bytes.resize(odd.bytes.size() - 3);
    SetBe16(odd.bytes, 14 + 2, static_cast<uint16_t>(odd.bytes.size() - 14));
    FixIpChecksum(odd.bytes);
    UdpExtractor extractor;
    EXPECT_TRUE(Extract(Capture({f[0], far, odd}), extractor).empty());
    EXPECT_EQ(extractor.stats().oversize_datagrams, 1u);
    EXPECT_EQ(extractor.stats().ip_malformed, 1u);
}

TEST(UdpExtractor, MemoryLimits) {
    std::mt19937 rng(10);
    std::vector<std::vector<IpFrame>> d;
    std::vector<std::string> payloads;
    for (int i = 0; i < 3; ++i) {
        payloads.push_back(test::RandomBytes(3000, rng));
        d.push_back(UdpFrames(kIpT0 + i, static_cast<uint16_t>(100 + i), payloads.back(), 1500,
                              static_cast<uint16_t>(i + 1)));
        ASSERT_EQ(d.back().size(), 3u);
    }
    ExtractorConfig config;
    config.max_datagrams_in_flight = 2;
    UdpExtractor limit(config);
    const auto got =
        Extract(Capture({d[0][0], d[1][0], d[2][0], d[1][1], d[1][2], d[2][1], d[2][2]}), limit);
    ASSERT_EQ(got.size(), 2u);
    EXPECT_EQ(got[0].payload, payloads[1]);
    EXPECT_EQ(got[1].payload, payloads[2]);
    EXPECT_EQ(limit.stats().evicted_datagrams_limit, 1u);

    // Two 40000-byte datagrams against a 65535-byte budget: the older one goes.
    const std::string big0 = test::RandomBytes(40000, rng), big1 = test::RandomBytes(40000, rng);
    auto b0 = UdpFrames(kIpT0, 1, big0, 1500, 7);
    auto b1 = UdpFrames(kIpT0 + 1, 2, big1, 1500, 8);
    b0.pop_back();
    for (IpFrame& f : b1) f.ts = kIpT0 + 1;
    std::vector<IpFrame> frames = b0;
    frames.insert(frames.end(), b1.begin(), b1.end());
    ExtractorConfig small;
    small.max_bytes_in_flight = 65535;
    UdpExtractor bytes(small);
    const auto got_bytes = Extract(Capture(frames), bytes);
    ASSERT_EQ(got_bytes.size(), 1u);
    EXPECT_EQ(got_bytes[0].payload, big1);
    EXPECT_EQ(bytes.stats().evicted_datagrams_bytes, 1u);
    EXPECT_EQ(bytes.stats().incomplete_at_end, 0u);

    ExtractorConfig bad;
    bad.max_bytes_in_flight = 1000;
    EXPECT_THROW(UdpExtractor{bad}, common::Error);
    bad = {};
    bad.max_datagrams_in_flight = 0;
    EXPECT_THROW(bad.Validate(), common::Error);
    bad = {};
    bad.reassembly_timeout = common::Duration{0};
    EXPECT_THROW(bad.Validate(), common::Error);
}

// Link-layer variants of an Ethernet frame.
std::string ToSll(const std::string& eth, uint16_t protocol = 0) {
    std::string h("\x00\x00\x00\x01\x00\x06", 6);
    h += eth.substr(6, 6) + std::string(2, '\0');
    h += protocol ? std::string{static_cast<char>(protocol >> 8), static_cast<char>(protocol)}
                  : eth.substr(12, 2);
    return h + eth.substr(14);
}
std::string ToSll2(const std::string& eth) {
    std::string h = eth.substr(12, 2) + std::string("\x00\x00\x00\x00\x00\x02\x00\x01\x00\x06", 10);
    h += eth.substr(6, 6) + std::string(2, '\0');
    return h + eth.substr(14);
}
std::string AddTags(const std::string& eth, const std::vector<uint16_t>& tpids) {
    std::string out = eth.substr(0, 12);
    for (size_t i = 0; i < tpids.size(); ++i) {
        out += std::string{static_cast<char>(tpids[i] >> 8), static_cast<char>(tpids[i])};
        out += std::string{'\x00', static_cast<char>(10 + i)};  // VLAN id
    }
    return out + eth.substr(12);
}

TEST(UdpExtractor, CookedCapturesAndVlanTags) {
    std::mt19937 rng(11);
    const std::string payload = test::RandomBytes(6464, rng);
    const auto eth = UdpFrames(kIpT0, 7502, payload, 1500);
    struct Variant {
        uint32_t link;
        std::function<std::string(const std::string&)> convert;
        bool tagged;
    };
    const std::vector<Variant> variants = {
        {kLinkTypeLinuxSll, [](const std::string& e) { return ToSll(e); }, false},
        {kLinkTypeLinuxSll2, ToSll2, false},
        {kLinkTypeEthernet, [](const std::string& e) { return AddTags(e, {kEtherTypeVlan}); },
         true},
        {kLinkTypeEthernet,
         [](const std::string& e) {
             return AddTags(e, {kEtherTypeQinQ, kEtherTypeVlan});
         },
         true},
        {kLinkTypeEthernet,
         [](const std::string& e) {
             return AddTags(e, {kEtherTypeQinQOld, kEtherTypeQinQ, kEtherTypeVlan});
         },
         true},
        {kLinkTypeLinuxSll,
         [](const std::string& e) { return ToSll(AddTags(e, {kEtherTypeVlan})); }, true},
        {kLinkTypeRaw, [](const std::string& e) { return e.substr(14); }, false},
        {kLinkTypeIpv4, [](const std::string& e) { return e.substr(14); }, false},
        {kLinkTypeNull,
         [](const std::string& e) { return std::string("\x02\0\0\0", 4) + e.substr(14); }, false},
        {kLinkTypeLoop,
         [](const std::string& e) { return std::string("\0\0\0\x02", 4) + e.substr(14); }, false},
    };
    for (size_t v = 0; v < variants.size(); ++v) {
        std::vector<IpFrame> frames;
        for (IpFrame f : eth) {
            f.bytes = variants[v].convert(f.bytes);
            frames.push_back(f);
        }
        UdpExtractor extractor;
        const auto got = Extract(Capture(frames, variants[v].link), extractor);
        ASSERT_EQ(got.size(), 1u) << "variant " << v;
        EXPECT_EQ(got[0].payload, payload) << "variant " << v;
        EXPECT_EQ(got[0].dport, 7502);
        EXPECT_EQ(extractor.stats().vlan_tagged, variants[v].tagged ? eth.size() : 0u)
            << "variant " << v;
    }
}

TEST(UdpExtractor, OtherTrafficIsCountedAndSkipped) {
    std::mt19937 rng(12);
    const std::string eth = UdpFrames(kIpT0, 7502, test::RandomBytes(100, rng), 0)[0].bytes;
    std::vector<IpFrame> frames;
    std::string arp = eth;
    SetBe16(arp, 12, 0x0806);
    std::string ipv6 = eth;
    SetBe16(ipv6, 12, 0x86DD);
    std::string llc = eth;
    SetBe16(llc, 12, 0x0100);
    std::string tcp = eth;
    tcp[14 + 9] = 6;
    FixIpChecksum(tcp);
    std::string short_eth = eth.substr(0, 10);
    std::string short_vlan = AddTags(eth, {kEtherTypeVlan}).substr(0, 15);
    std::string bad_version = eth;
    bad_version[14] = 0x65;
    std::string bad_ihl = eth;
    bad_ihl[14] = 0x44;
    for (const std::string& b :
         {arp, ipv6, llc, tcp, short_eth, short_vlan, bad_version, bad_ihl}) {
        frames.push_back({kIpT0, b, kLinkTypeEthernet});
    }
    UdpExtractor extractor;
    PcapRecord record;
    UdpDatagram out;
    for (const IpFrame& f : frames) {
        record.link_type = f.link;
        record.data = test::AsBytes(f.bytes);
        EXPECT_FALSE(extractor.Feed(record, out));
    }
    // SocketCAN and cooked CAN (protocol 0x000C) are not IP.
    const std::string can("\x00\x00\x01\x2a\x08\x00\x00\x00\x01\x02\x03\x04\x05\x06\x07\x08", 16);
    EXPECT_FALSE(extractor.FeedFrame(kLinkTypeCanSocketcan, kIpT0, test::AsBytes(can), 0, out));
    const std::string cooked_can = ToSll(std::string(12, '\0') + "xx" + can, 0x000C);
    EXPECT_FALSE(extractor.FeedFrame(kLinkTypeLinuxSll, kIpT0, test::AsBytes(cooked_can), 0, out));
    const ExtractorStats& s = extractor.stats();
    EXPECT_EQ(s.records, 10u);
    EXPECT_EQ(s.not_ipv4, 4u);  // ARP, IPv6, LLC, cooked CAN
    EXPECT_EQ(s.not_udp, 1u);
    EXPECT_EQ(s.link_truncated, 2u);
    EXPECT_EQ(s.ip_malformed, 2u);
    EXPECT_EQ(s.unsupported_link_type, 1u);
    EXPECT_EQ(s.datagrams, 0u);
}

TEST(UdpExtractor, ChecksumsAndLengths) {
    std::mt19937 rng(13);
    const std::string eth = UdpFrames(kIpT0, 7502, test::RandomBytes(100, rng), 0)[0].bytes;
    std::string bad_ip = eth;
    bad_ip[14 + 8] = 1;  // TTL changed, checksum not
    std::string bad_udp = eth;
    bad_udp[eth.size() - 1] ^= 1;
    std::string no_udp_sum = bad_udp;
    SetBe16(no_udp_sum, 14 + 20 + 6, 0);
    std::string long_udp = eth;
    SetBe16(long_udp, 14 + 20 + 4, 200);
    std::string short_udp = eth;
    SetBe16(short_udp, 14 + 20 + 4, 7);
    std::string padded = eth + std::string(20, '\0');  // Ethernet padding / FCS after the packet
    ExtractorConfig config;
    EXPECT_FALSE(config.drop_bad_ip_checksum);  // counted, not dropped, by default (issue 16)
    config.drop_bad_ip_checksum = true;
    config.check_udp_checksum = true;
    {
        UdpExtractor extractor(config);
        UdpDatagram out;
        auto feed = [&](const std::string& b) {
            return extractor.FeedFrame(kLinkTypeEthernet, kIpT0, test::AsBytes(b), 0, out);
        };
        EXPECT_FALSE(feed(bad_ip));
        EXPECT_FALSE(feed(bad_udp));
        EXPECT_TRUE(feed(no_udp_sum));
        EXPECT_FALSE(feed(long_udp));
        EXPECT_FALSE(feed(short_udp));
        EXPECT_TRUE(feed(padded));
        EXPECT_EQ(out.payload.size(), 100u);
        EXPECT_FALSE(feed(eth.substr(0, eth.size() - 1)));  // cut by the snaplen
        EXPECT_FALSE(feed(eth.substr(0, 14 + 12)));
        const ExtractorStats& s = extractor.stats();
        EXPECT_EQ(s.ip_bad_checksum, 1u);
        EXPECT_EQ(s.udp_bad_checksum, 1u);
        EXPECT_EQ(s.udp_bad_length, 2u);
        EXPECT_EQ(s.ip_truncated, 2u);
        EXPECT_EQ(s.datagrams, 2u);
    }
    config.drop_bad_ip_checksum = false;
    config.check_udp_checksum = false;
    UdpExtractor lenient(config);
    UdpDatagram out;
    EXPECT_TRUE(lenient.FeedFrame(kLinkTypeEthernet, kIpT0, test::AsBytes(bad_ip), 0, out));
    EXPECT_TRUE(lenient.FeedFrame(kLinkTypeEthernet, kIpT0, test::AsBytes(bad_udp), 0, out));
    EXPECT_EQ(lenient.stats().ip_bad_checksum, 1u);
}

TEST(UdpExtractor, GuessesPortsFromPayloadSizes) {
    std::vector<UdpDatagram> datagrams;
    static const std::vector<uint8_t> bytes(6464);
    auto add = [&](uint16_t port, size_t size, int n) {
        for (int i = 0; i < n; ++i) {
            UdpDatagram d;
            d.dst_port = port;
            d.payload = std::span<const uint8_t>(bytes.data(), size);
            datagrams.push_back(d);
        }
    };
    add(5353, 100, 20);
    add(9999, 6464, 5);
    add(7502, 6464, 64);
    add(7503, 48, 10);
    add(7502, 48, 1);
    PortGuess g = GuessPorts(datagrams, 6464, 48);
    EXPECT_EQ(g.lidar_port, 7502);
    EXPECT_EQ(g.lidar_datagrams, 64u);
    EXPECT_EQ(g.imu_port, 7503);
    EXPECT_EQ(g.imu_datagrams, 10u);
    EXPECT_EQ(g.datagrams, 100u);
    g = GuessPorts(datagrams, 8448, 0);
    EXPECT_FALSE(g.lidar_port);
    EXPECT_FALSE(g.imu_port);

    // From a capture file.
    std::mt19937 rng(14);
    PcapWriter writer;
    for (int i = 0; i < 20; ++i) {
        writer.WriteUdp(kIpT0 + i * 1000, kSensorIp, 7502, kHostIp, 7600,
                        test::AsBytes(test::RandomBytes(6464, rng)), 1500);
        if (i % 5 == 0) {
            writer.WriteUdp(kIpT0 + i * 1000, kSensorIp, 7503, kHostIp, 7601,
                            test::AsBytes(test::RandomBytes(48, rng)), 1500);
        }
    }
    test::TempDir dir;
    test::WriteBytes(dir / "c.pcap", writer.bytes());
    g = GuessPortsInCapture(dir / "c.pcap", 6464, 48);
    EXPECT_EQ(g.lidar_port, 7600);
    EXPECT_EQ(g.imu_port, 7601);
    EXPECT_EQ(g.lidar_datagrams, 20u);
    EXPECT_EQ(g.imu_datagrams, 4u);
}

// Mutants of captures (classic with fragments, pcapng, cooked) through reader and extractor:
// they end cleanly or throw common::FileError naming the input, nothing else.
TEST(UdpExtractor, MutationFuzz) {
    std::mt19937 rng(15);
    PcapWriter classic;
    for (int i = 0; i < 6; ++i) {
        classic.WriteUdp(kIpT0 + i * 1000, kSensorIp, 7502, kHostIp, 7502,
                         test::AsBytes(test::RandomBytes(i % 2 ? 3000 : 40, rng)), 600);
    }
    std::vector<IpFrame> frames = Frames(classic.bytes());
    std::vector<IpFrame> cooked = frames;
    for (IpFrame& f : cooked) f.bytes = ToSll2(AddTags(f.bytes, {kEtherTypeVlan}));
    // pcapng, written by hand: section header, interface, enhanced packet blocks.
    auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
    auto block = [&](uint32_t type, std::string body) {
        while (body.size() % 4) body.push_back('\0');
        const uint32_t length = static_cast<uint32_t>(body.size() + 12);
        return u32(type) + u32(length) + body + u32(length);
    };
    std::string ng =
        block(0x0A0D0D0A, u32(0x1A2B3C4D) + std::string("\x01\0\0\0", 4) + std::string(8, '\xff'));
    ng +=
        block(1, std::string("\x01\0\0\0", 4) + u32(0) + std::string("\x09\0\x01\0\x09\0\0\0", 8));
    for (const IpFrame& f : frames) {
        ng += block(6, u32(0) + u32(0) + u32(static_cast<uint32_t>(f.ts)) +
                           u32(static_cast<uint32_t>(f.bytes.size())) +
                           u32(static_cast<uint32_t>(f.bytes.size())) + f.bytes);
    }
    const std::vector<test::FuzzSeed> seeds = {
        {classic.bytes(), 24 + 16 + 14 + 20 + 8},
        {Capture(cooked, kLinkTypeLinuxSll2), 24 + 16 + 24 + 20 + 8},
        {ng, 120},
    };
    ExtractorConfig config;
    config.check_udp_checksum = true;
    UdpExtractor extractor(config);
    const auto counts = test::FuzzReader(
        "fuzz.pcap", seeds, 4000, 16, test::kMutationBytes, [&](const std::string& bytes) {
            PcapReader reader = PcapReader::FromMemory("fuzz.pcap", bytes);
            PcapRecord r;
            UdpDatagram d;
            while (reader.Next(r)) {
                if (extractor.Feed(r, d)) {
                    EXPECT_LE(d.payload.size(), 65507u);
                }
            }
            extractor.Finish();
        });
    EXPECT_GT(counts.rejected, 0u);
    EXPECT_GT(counts.accepted, 0u);
    EXPECT_GT(extractor.stats().datagrams, 0u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::net
