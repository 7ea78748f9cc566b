#include "drivers/net/pcap_writer.hpp"

#include <fcntl.h>
#include <unistd.h>

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
    fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) {
        throw FileError(StatusCode::kIoError, name_, 0,
                        std::string("cannot create: ") + std::strerror(errno));
    }
    buffer_.resize(kWriteBufferBytes);
    frame_.reserve(65536 + 64);
    WriteHeader();
}

PcapWriter::PcapWriter(const PcapWriterConfig& config, std::string name)
    : config_(config), name_(std::move(name)), memory_mode_(true), next_ip_id_(config.first_ip_id) {
    config_.Validate();
    frame_.reserve(65536 + 64);
    WriteHeader();
}

PcapWriter::~PcapWriter() {
    if (fd_ >= 0) {
        try {
            Flush();
        } catch (const FileError&) {
            // Quietly: Close() is the place to see write errors.
        }
        ::close(fd_);
    }
}

void PcapWriter::Fail(const std::string& what) const {
    throw FileError(StatusCode::kIoError, name_, 0, what);
}

void PcapWriter::WriteHeader() {
    // Host byte order (little-endian here), as libpcap writes: the magic tells readers.
    uint8_t h[24];
    const uint32_t magic = config_.nanosecond ? 0xA1B23C4D : 0xA1B2C3D4;
    const uint16_t major = 2;
    const uint16_t minor = 4;
    const uint32_t zero = 0;
    std::memcpy(h, &magic, 4);
    std::memcpy(h + 4, &major, 2);
    std::memcpy(h + 6, &minor, 2);
    std::memcpy(h + 8, &zero, 4);   // thiszone
    std::memcpy(h + 12, &zero, 4);  // sigfigs
    std::memcpy(h + 16, &config_.snaplen, 4);
    std::memcpy(h + 20, &config_.link_type, 4);
    Put(h, sizeof(h));
}

void PcapWriter::Put(const void* data, size_t size) {
    if (closed_) Fail("write after Close()");
    if (memory_mode_) {
        memory_.append(static_cast<const char*>(data), size);
        return;
    }
    const uint8_t* p = static_cast<const uint8_t*>(data);
    while (size > 0) {
        if (buffered_ == buffer_.size()) Flush();
        const size_t step = std::min(size, buffer_.size() - buffered_);
        std::memcpy(buffer_.data() + buffered_, p, step);
        buffered_ += step;
        p += step;
        size -= step;
    }
}

void PcapWriter::Flush() {
    if (memory_mode_ || fd_ < 0) return;
    size_t done = 0;
    while (done < buffered_) {
        const ssize_t n = ::write(fd_, buffer_.data() + done, buffered_ - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            buffered_ = 0;
            Fail(std::string("write failed: ") + std::strerror(errno));
        }
        done += static_cast<size_t>(n);
    }
    buffered_ = 0;
}

void PcapWriter::Close() {
    if (closed_) return;
    Flush();
    closed_ = true;
    if (fd_ >= 0) {
        const int fd = fd_;
        fd_ = -1;
        if (::close(fd) != 0) Fail(std::string("close failed: ") + std::strerror(errno));
    }
}

void PcapWriter::WriteRecord(int64_t timestamp_ns, std::span<const uint8_t> bytes,
                             uint32_t original_length) {
    if (timestamp_ns < 0 || timestamp_ns / 1'000'000'000 > 0xFFFFFFFFll) {
        throw Error(StatusCode::kInvalidArgument, name_ + ": timestamp " +
                                                      std::to_string(timestamp_ns) +
                                                      " ns is outside the pcap range [0, 2^32 s)");
    }
    if (bytes.size() > 0xFFFFFFFFu) {
        throw Error(StatusCode::kInvalidArgument, name_ + ": record larger than 4 GiB");
    }
    const uint32_t caplen = static_cast<uint32_t>(std::min<size_t>(bytes.size(), config_.snaplen));
    const uint32_t fields[4] = {
        static_cast<uint32_t>(timestamp_ns / 1'000'000'000),
        static_cast<uint32_t>(config_.nanosecond ? timestamp_ns % 1'000'000'000
                                                 : timestamp_ns % 1'000'000'000 / 1000),
        caplen,
        std::max(static_cast<uint32_t>(bytes.size()), original_length),
    };
    Put(fields, sizeof(fields));
    Put(bytes.data(), caplen);
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
