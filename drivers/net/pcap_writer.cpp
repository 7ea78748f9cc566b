// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/net/pcap_writer.hpp"

#include <pcap/pcap.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "algorithms/common/status.hpp"
#include "drivers/net/byte_order.hpp"
#include "drivers/net/ipv4.hpp"

namespace bimslam::net {
namespace {
using detail::PutBe16;
using detail::PutBe32;

using common::Error;
using common::FileError;
using common::StatusCode;

constexpr size_t kWriteBufferBytes = 256 * 1024;
constexpr size_t kIpHeaderBytes = 20;
constexpr size_t kUdpHeaderBytes = 8;
constexpr size_t kMaxUdpPayload = 65535 - kIpHeaderBytes - kUdpHeaderBytes;  // 65507

// pcap_open_dead takes libpcap's DLT_ number, which differs from the file's link type for a few
// types (libpcap's linktype_to_dlt; pcap/dlt.h): here, those below 104 it renumbers.
int LinkTypeToDlt(uint32_t link_type) {
    switch (link_type) {
        case 100:
            return DLT_ATM_RFC1483;
        case kLinkTypeRaw:
            return DLT_RAW;
        case 102:
            return DLT_SLIP_BSDOS;
        case 103:
            return DLT_PPP_BSDOS;
        default:
            return static_cast<int>(link_type);
    }
}

// The memory writer's stream: appends to the std::string behind the cookie.
ssize_t AppendToString(void* cookie, const char* data, size_t size) {
    static_cast<std::string*>(cookie)->append(data, size);
    return static_cast<ssize_t>(size);
}

}  // namespace

void PcapWriterConfig::Validate() const {
    if (snaplen == 0 || snaplen > PcapReader::kMaxCaptureBytes) {
        throw Error(StatusCode::kInvalidArgument,
                    "snaplen: " + std::to_string(snaplen) + ", must be in [1, " +
                        std::to_string(PcapReader::kMaxCaptureBytes) + "]");
    }
    if (link_type > 0xFFFF) {
        throw Error(StatusCode::kInvalidArgument,
                    "link_type: " + std::to_string(link_type) + ", must fit 16 bits");
    }
    if (ttl == 0) throw Error(StatusCode::kInvalidArgument, "ttl: 0, must be positive");
}

PcapWriter::PcapWriter(const std::filesystem::path& path, const PcapWriterConfig& config)
    : config_(config), name_(path.string()), next_ip_id_(config.first_ip_id) {
    config_.Validate();
    FILE* file = std::fopen(path.c_str(), "wbe");  // e: O_CLOEXEC
    if (file == nullptr) {
        throw FileError(StatusCode::kIoError, name_, 0,
                        std::string("cannot create: ") + std::strerror(errno));
    }
    buffer_.resize(kWriteBufferBytes);
    std::setvbuf(file, buffer_.data(), _IOFBF, buffer_.size());
    Open(file);
}

PcapWriter::PcapWriter(const PcapWriterConfig& config, std::string name)
    : config_(config), name_(std::move(name)), next_ip_id_(config.first_ip_id) {
    config_.Validate();
    // Unbuffered, so that bytes() holds every record as soon as it is written.
    FILE* file = fopencookie(&memory_, "wb", {nullptr, AppendToString, nullptr, nullptr});
    if (file == nullptr) Fail(std::string("fopencookie: ") + std::strerror(errno));
    std::setvbuf(file, nullptr, _IONBF, 0);
    Open(file);
}

// libpcap writes the file header (magic by precision, version 2.4, snaplen, link type) when the
// dumper opens; it takes the stream.
void PcapWriter::Open(FILE* file) {
    dead_ = pcap_open_dead_with_tstamp_precision(
        LinkTypeToDlt(config_.link_type), static_cast<int>(config_.snaplen),
        config_.nanosecond ? PCAP_TSTAMP_PRECISION_NANO : PCAP_TSTAMP_PRECISION_MICRO);
    if (dead_ != nullptr) dumper_ = pcap_dump_fopen(dead_, file);
    if (dumper_ == nullptr) {
        std::fclose(file);
        const std::string why = dead_ != nullptr ? pcap_geterr(dead_) : "pcap_open_dead failed";
        if (dead_ != nullptr) pcap_close(dead_);
        dead_ = nullptr;
        Fail(why);
    }
    file_ = file;
    frame_.reserve(65536 + 64);
}

PcapWriter::~PcapWriter() {
    if (dumper_ != nullptr) pcap_dump_close(dumper_);  // quietly: Close() reports write errors
    if (dead_ != nullptr) pcap_close(dead_);
}

void PcapWriter::Fail(const std::string& what) const {
    throw FileError(StatusCode::kIoError, name_, 0, what);
}

void PcapWriter::Flush() {
    if (closed_) return;
    if (pcap_dump_flush(dumper_) != 0 || std::ferror(file_) != 0) {
        Fail(std::string("write failed: ") + std::strerror(errno));
    }
}

void PcapWriter::Close() {
    if (closed_) return;
    const int flushed = pcap_dump_flush(dumper_);
    const int err = errno;
    const bool failed = flushed != 0 || std::ferror(file_) != 0;
    pcap_dump_close(dumper_);
    dumper_ = nullptr;
    file_ = nullptr;
    closed_ = true;
    if (failed) Fail(std::string("write failed: ") + std::strerror(err));
}

void PcapWriter::WriteRecord(int64_t timestamp_ns, std::span<const uint8_t> bytes,
                             uint32_t original_length) {
    if (closed_) Fail("write after Close()");
    if (timestamp_ns < 0 || timestamp_ns / 1'000'000'000 > 0xFFFFFFFFll) {
        throw Error(StatusCode::kInvalidArgument, name_ + ": timestamp " +
                                                      std::to_string(timestamp_ns) +
                                                      " ns is outside the pcap range [0, 2^32 s)");
    }
    if (bytes.size() > 0xFFFFFFFFu) {
        throw Error(StatusCode::kInvalidArgument, name_ + ": record larger than 4 GiB");
    }
    pcap_pkthdr header{};
    // libpcap stores ts_sec as 32 bits: values from 2^31 to 2^32 s keep their bits. With the
    // nanosecond precision tv_usec holds nanoseconds.
    header.ts.tv_sec = static_cast<time_t>(timestamp_ns / 1'000'000'000);
    header.ts.tv_usec = static_cast<suseconds_t>(
        config_.nanosecond ? timestamp_ns % 1'000'000'000 : timestamp_ns % 1'000'000'000 / 1000);
    header.caplen = static_cast<uint32_t>(std::min<size_t>(bytes.size(), config_.snaplen));
    header.len = std::max(static_cast<uint32_t>(bytes.size()), original_length);
    pcap_dump(reinterpret_cast<u_char*>(dumper_), &header, bytes.data());
    // pcap_dump reports nothing: a failed write shows in the stream's error flag.
    if (std::ferror(file_) != 0) Fail(std::string("write failed: ") + std::strerror(errno));
    ++records_;
}

void PcapWriter::WriteUdp(int64_t timestamp_ns, uint32_t src_ip, uint16_t src_port, uint32_t dst_ip,
                          uint16_t dst_port, std::span<const uint8_t> payload, uint32_t mtu) {
    size_t link_header = 0;
    if (config_.link_type == kLinkTypeEthernet) {
        link_header = 14;
    } else if (config_.link_type != kLinkTypeRaw && config_.link_type != kLinkTypeIpv4) {
        throw Error(StatusCode::kInvalidArgument,
                    name_ +
                        ": WriteUdp needs link type Ethernet (1), raw (101) or IPv4 (228), not " +
                        std::to_string(config_.link_type));
    }
    if (payload.size() > kMaxUdpPayload) {
        throw Error(
            StatusCode::kInvalidArgument,
            name_ + ": UDP payload of " + std::to_string(payload.size()) + " bytes exceeds 65507");
    }
    if (mtu != 0 && mtu < kIpHeaderBytes + 8) {
        throw Error(StatusCode::kInvalidArgument,
                    name_ + ": mtu " + std::to_string(mtu) + " below 28 (0: no fragmentation)");
    }
    // The whole IP payload (UDP header + data), cut into fragments below.
    const size_t udp_length = kUdpHeaderBytes + payload.size();
    uint8_t udp[kUdpHeaderBytes];
    PutBe16(udp, src_port);
    PutBe16(udp + 2, dst_port);
    PutBe16(udp + 4, static_cast<uint16_t>(udp_length));
    PutBe16(udp + 6, 0);
    if (config_.udp_checksum) {
        // Pseudo-header (source, destination, zero, protocol, UDP length), header, data. The
        // data sum is taken over the payload alone: its offset (8) is even, so words align.
        const uint32_t pseudo = (src_ip >> 16) + (src_ip & 0xFFFF) + (dst_ip >> 16) +
                                (dst_ip & 0xFFFF) + kIpProtocolUdp +
                                static_cast<uint32_t>(udp_length);
        const uint16_t data_sum = static_cast<uint16_t>(~InternetChecksum(payload) & 0xFFFF);
        uint16_t sum =
            InternetChecksum(std::span<const uint8_t>(udp, kUdpHeaderBytes), pseudo + data_sum);
        if (sum == 0) sum = 0xFFFF;  // 0 means "no checksum" (RFC 768)
        PutBe16(udp + 6, sum);
    }
    const uint16_t id = next_ip_id_++;
    // Bytes of IP payload per fragment: all of it when it fits, else (mtu - 20) & ~7.
    const size_t fits = mtu == 0 ? udp_length : mtu - kIpHeaderBytes;
    const size_t chunk = udp_length <= fits ? udp_length : (fits & ~size_t{7});
    size_t offset = 0;
    do {
        const size_t length = std::min(chunk, udp_length - offset);
        const bool more = offset + length < udp_length;
        frame_.resize(link_header + kIpHeaderBytes + length);
        uint8_t* f = frame_.data();
        if (link_header != 0) {
            std::memcpy(f, config_.destination_mac.data(), 6);
            std::memcpy(f + 6, config_.source_mac.data(), 6);
            PutBe16(f + 12, kEtherTypeIpv4);
        }
        uint8_t* ip = f + link_header;
        ip[0] = 0x45;  // version 4, 5 words of header
        ip[1] = 0;     // DSCP/ECN
        PutBe16(ip + 2, static_cast<uint16_t>(kIpHeaderBytes + length));
        PutBe16(ip + 4, id);
        PutBe16(ip + 6, static_cast<uint16_t>((more ? 0x2000 : 0) | (offset / 8)));
        ip[8] = config_.ttl;
        ip[9] = kIpProtocolUdp;
        PutBe16(ip + 10, 0);
        PutBe32(ip + 12, src_ip);
        PutBe32(ip + 16, dst_ip);
        PutBe16(ip + 10, InternetChecksum(std::span<const uint8_t>(ip, kIpHeaderBytes)));
        // IP payload bytes [offset, offset + length): the UDP header lies in [0, 8).
        uint8_t* out = ip + kIpHeaderBytes;
        size_t at = offset;
        if (at < kUdpHeaderBytes) {
            const size_t n = std::min(kUdpHeaderBytes - at, length);
            std::memcpy(out, udp + at, n);
            out += n;
            at += n;
        }
        const size_t rest = offset + length - at;
        if (rest > 0) std::memcpy(out, payload.data() + (at - kUdpHeaderBytes), rest);
        WriteRecord(timestamp_ns, frame_);
        offset += length;
    } while (offset < udp_length);
}

}  // namespace bimslam::net
