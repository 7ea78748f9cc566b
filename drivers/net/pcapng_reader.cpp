// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/net/pcapng_reader.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "algorithms/common/status.hpp"

namespace bimslam::net::detail {
namespace {

using common::FileError;
using common::StatusCode;

// Block types and the byte-order magic (draft-ietf-opsawg-pcapng, section 4).
constexpr uint32_t kBlockSectionHeader = 0x0A0D0D0A;  // the same in both byte orders
constexpr uint32_t kBlockInterfaceDescription = 0x00000001;
constexpr uint32_t kBlockPacketObsolete = 0x00000002;
constexpr uint32_t kBlockSimplePacket = 0x00000003;
constexpr uint32_t kBlockEnhancedPacket = 0x00000006;
constexpr uint32_t kByteOrderMagic = 0x1A2B3C4D;
constexpr uint16_t kOptionEnd = 0;
constexpr uint16_t kOptionIfTsresol = 9;
constexpr uint16_t kOptionIfTsoffset = 14;
constexpr size_t kMaxInterfaces = 1 << 16;  // per section; a guard against corrupt files only

// The buffer holds the largest loaded block twice over, so a refill always makes room.
constexpr uint32_t kMaxLoadedBlockBytes = PcapReader::kMaxLoadedBlockBytes;
constexpr size_t kBufferBytes = 2 * static_cast<size_t>(kMaxLoadedBlockBytes);

// Timestamps are 64-bit counts of 10^-n or 2^-n seconds: the conversion to nanoseconds needs
// 128-bit intermediates (a GCC/Clang extension).
__extension__ typedef __int128 Int128;
__extension__ typedef unsigned __int128 UInt128;

uint32_t Swap32(uint32_t v) { return __builtin_bswap32(v); }

}  // namespace

PcapNgReader::PcapNgReader(std::string name, FILE* file, const GzipStatus* gzip)
    : name_(std::move(name)), file_(file), gzip_(gzip), buffer_(kBufferBytes) {
    data_ = buffer_.data();
    ReadFileHeader();
}

PcapNgReader::PcapNgReader(std::string name, std::span<const uint8_t> bytes)
    : name_(std::move(name)), data_(bytes.data()), size_(bytes.size()), eof_(true) {
    ReadFileHeader();
}

void PcapNgReader::Fail(uint64_t offset, const std::string& what) const {
    throw FileError(StatusCode::kParseError, name_, 0,
                    "at byte " + std::to_string(offset) + ": " + what);
}

void PcapNgReader::ReadError() const {
    ThrowReadError(name_, gzip_, data_offset_ + size_, std::strerror(errno));
}

uint16_t PcapNgReader::U16(const uint8_t* p) const {
    uint16_t v;
    std::memcpy(&v, p, 2);
    return swapped_ ? static_cast<uint16_t>((v >> 8) | (v << 8)) : v;
}

uint32_t PcapNgReader::U32(const uint8_t* p) const {
    uint32_t v;
    std::memcpy(&v, p, 4);
    return swapped_ ? Swap32(v) : v;
}

// Makes `n` (<= kBufferBytes / 2) bytes available at data_ + pos_, reading more of the file when
// needed; false when the file ends first.
bool PcapNgReader::Ensure(size_t n) {
    if (Available() >= n) return true;
    if (file_ == nullptr || eof_) return false;
    std::memmove(buffer_.data(), buffer_.data() + pos_, Available());
    data_offset_ += pos_;
    size_ -= pos_;
    pos_ = 0;
    while (size_ < n && !eof_) {
        const size_t got = std::fread(buffer_.data() + size_, 1, buffer_.size() - size_, file_);
        if (got == 0) {
            if (std::ferror(file_)) ReadError();
            eof_ = true;
            if (gzip_ != nullptr && gzip_->cut) truncated_ = true;
        }
        size_ += got;
    }
    return size_ >= n;
}

// Skips `n` bytes; false when the file ends first.
bool PcapNgReader::Skip(uint64_t n) {
    while (n > 0) {
        if (Available() == 0 && !Ensure(1)) return false;
        const size_t step = static_cast<size_t>(std::min<uint64_t>(n, Available()));
        pos_ += step;
        n -= step;
    }
    return true;
}

// The file ended inside a block that starts at the current position.
bool PcapNgReader::EndTruncated() {
    truncated_ = true;
    truncated_bytes_ = Available();
    pos_ = size_;
    done_ = true;
    return false;
}

// Sets the byte order from the magic of the section header block at data_ + pos_.
void PcapNgReader::ReadByteOrder(uint64_t offset) {
    uint32_t bom;
    std::memcpy(&bom, data_ + pos_ + 8, 4);
    if (bom == kByteOrderMagic) {
        swapped_ = false;
    } else if (bom == Swap32(kByteOrderMagic)) {
        swapped_ = true;
    } else {
        char hex[16];
        std::snprintf(hex, sizeof(hex), "0x%08X", bom);
        Fail(offset + 8, std::string("bad pcapng byte-order magic ") + hex);
    }
}

// A block repeats its length at its end.
void PcapNgReader::CheckTrailer(const uint8_t* block, uint32_t length, uint64_t offset) const {
    const uint32_t trailer = U32(block + length - 4);
    if (trailer != length) {
        Fail(offset, "block length " + std::to_string(length) + " at the start, " +
                         std::to_string(trailer) + " at the end");
    }
}

void PcapNgReader::ReadFileHeader() {
    // The first block must be a complete section header: unlike a later block that the file
    // ends in, a broken one here is an error, not a truncated capture.
    if (!Ensure(12)) Fail(0, "file ends inside the pcapng section header block");
    ReadByteOrder(0);
    const uint32_t length = U32(data_ + pos_ + 4);
    if (length < 28 || length % 4 != 0 || length > kMaxLoadedBlockBytes) {
        Fail(4, "bad section header block length " + std::to_string(length));
    }
    if (!Ensure(length)) {
        Fail(0, "file ends inside the pcapng section header block (" + std::to_string(Available()) +
                    " of " + std::to_string(length) + " bytes)");
    }
    CheckTrailer(data_ + pos_, length, 0);
    ReadSectionHeader(data_ + pos_, length, 0);
    pos_ += length;
    // The interface blocks that follow (libpcap, dumpcap and Wireshark write them before any
    // packet) give link_type() before the first record; anything else is left to Next().
    while (Ensure(8) && U32(data_ + pos_) == kBlockInterfaceDescription) {
        const uint64_t offset = Offset();
        const uint32_t block_length = U32(data_ + pos_ + 4);
        if (block_length < 20 || block_length % 4 != 0 || block_length > kMaxLoadedBlockBytes ||
            !Ensure(block_length)) {
            break;
        }
        CheckTrailer(data_ + pos_, block_length, offset);
        ReadInterface(data_ + pos_, block_length, offset);
        pos_ += block_length;
    }
}

int64_t PcapNgReader::Time(const Interface& itf, uint32_t high, uint32_t low,
                           uint64_t offset) const {
    // if_tsresol: bit 7 clear, 10^-n seconds; set, 2^-n seconds (pcapng, "if_tsresol").
    const UInt128 units = (static_cast<UInt128>(high) << 32) | low;
    const int exponent = itf.tsresol & 0x7F;
    Int128 ns = 0;
    if (itf.tsresol & 0x80) {
        ns = static_cast<Int128>((units * 1'000'000'000u) >> exponent);
    } else if (exponent <= 9) {
        UInt128 scale = 1;
        for (int i = exponent; i < 9; ++i) scale *= 10;
        ns = static_cast<Int128>(units * scale);
    } else if (exponent - 9 < 20) {  // 10^20 > 2^64: a larger divisor gives 0
        UInt128 scale = 1;
        for (int i = 9; i < exponent; ++i) scale *= 10;
        ns = static_cast<Int128>(units / scale);
    }
    ns += static_cast<Int128>(itf.tsoffset_s) * 1'000'000'000;
    if (ns > INT64_MAX || ns < INT64_MIN) {
        Fail(offset, "timestamp does not fit int64 nanoseconds (after the year 2262)");
    }
    return static_cast<int64_t>(ns);
}

void PcapNgReader::ReadSectionHeader(const uint8_t* block, uint32_t length, uint64_t offset) {
    if (length < 28)
        Fail(offset, "section header block length " + std::to_string(length) + " < 28");
    const uint16_t major = U16(block + 12);
    if (major != 1) {
        Fail(offset + 12, "unsupported pcapng version " + std::to_string(major) + "." +
                              std::to_string(U16(block + 14)) + " (only 1.x)");
    }
    interfaces_.clear();  // interface ids are per section
}

void PcapNgReader::ReadInterface(const uint8_t* block, uint32_t length, uint64_t offset) {
    if (length < 20) {
        Fail(offset, "interface description block length " + std::to_string(length) + " < 20");
    }
    if (interfaces_.size() >= kMaxInterfaces) {
        Fail(offset, "more than " + std::to_string(kMaxInterfaces) + " interfaces in a section");
    }
    Interface itf;
    itf.link_type = U16(block + 8);
    itf.snaplen = U32(block + 12);
    // Options: (code u16, length u16, value padded to 4 bytes)..., up to the trailing length.
    size_t at = 16;
    const size_t end = length - 4;
    while (at + 4 <= end) {
        const uint16_t code = U16(block + at);
        const uint16_t option_length = U16(block + at + 2);
        if (code == kOptionEnd) break;
        const size_t padded = (static_cast<size_t>(option_length) + 3) & ~size_t{3};
        if (at + 4 + padded > end) {
            Fail(offset + at, "interface option " + std::to_string(code) + " of " +
                                  std::to_string(option_length) + " bytes runs past the block end");
        }
        const uint8_t* value = block + at + 4;
        if (code == kOptionIfTsresol && option_length == 1) {
            itf.tsresol = value[0];
        } else if (code == kOptionIfTsoffset && option_length == 8) {
            // One 64-bit value in the section's byte order.
            const uint64_t first = U32(value);
            const uint64_t second = U32(value + 4);
            itf.tsoffset_s =
                static_cast<int64_t>(swapped_ ? (first << 32) | second : (second << 32) | first);
        }
        at += 4 + padded;
    }
    if (interfaces_.empty()) {
        link_type_ = itf.link_type;
        snaplen_ = itf.snaplen;
    }
    interfaces_.push_back(itf);
}

bool PcapNgReader::Next(PcapRecord& record, uint64_t records) {
    if (done_) return false;
    for (;;) {
        if (!Ensure(8)) {
            if (Available() == 0) {
                done_ = true;
                return false;
            }
            return EndTruncated();
        }
        const uint64_t offset = Offset();
        uint32_t type;
        std::memcpy(&type, data_ + pos_, 4);
        if (type == kBlockSectionHeader) {
            // A new section may switch the byte order: read it from the byte-order magic.
            if (!Ensure(12)) return EndTruncated();
            ReadByteOrder(offset);
        } else {
            type = U32(data_ + pos_);
        }
        const uint32_t length = U32(data_ + pos_ + 4);
        if (length < 12 || length % 4 != 0) {
            Fail(offset, "bad block length " + std::to_string(length) + " (block type " +
                             std::to_string(type) + "): not a multiple of 4 of at least 12");
        }
        const bool loaded = type == kBlockSectionHeader || type == kBlockInterfaceDescription ||
                            type == kBlockEnhancedPacket || type == kBlockSimplePacket ||
                            type == kBlockPacketObsolete;
        if (!loaded) {
            // Skipped whatever its size; its trailing length must still match.
            if (!Skip(length - 4) || !Ensure(4)) return EndTruncated();
            if (U32(data_ + pos_) != length) {
                Fail(offset, "block length " + std::to_string(length) + " at the start, " +
                                 std::to_string(U32(data_ + pos_)) + " at the end");
            }
            pos_ += 4;
            ++skipped_blocks_;
            continue;
        }
        if (length > kMaxLoadedBlockBytes) {
            Fail(offset, "block length " + std::to_string(length) + " (block type " +
                             std::to_string(type) + ") exceeds " +
                             std::to_string(kMaxLoadedBlockBytes));
        }
        if (!Ensure(length)) return EndTruncated();
        const uint8_t* block = data_ + pos_;
        CheckTrailer(block, length, offset);
        if (type == kBlockSectionHeader) {
            ReadSectionHeader(block, length, offset);
            pos_ += length;
            continue;
        }
        if (type == kBlockInterfaceDescription) {
            ReadInterface(block, length, offset);
            pos_ += length;
            continue;
        }
        // A packet block.
        uint32_t interface_id = 0;
        uint32_t caplen = 0;
        uint32_t original = 0;
        uint32_t high = 0;
        uint32_t low = 0;
        size_t header = 0;
        if (type == kBlockSimplePacket) {
            if (length < 16) Fail(offset, "simple packet block length " + std::to_string(length));
            header = 12;
            original = U32(block + 8);
            caplen = std::min<uint32_t>(original, length - 16);
        } else {
            if (length < 32)
                Fail(offset, "packet block length " + std::to_string(length) + " < 32");
            header = 28;
            interface_id = type == kBlockEnhancedPacket ? U32(block + 8) : U16(block + 8);
            high = U32(block + 12);
            low = U32(block + 16);
            caplen = U32(block + 20);
            original = U32(block + 24);
            if (caplen > length - 32) {
                Fail(offset, "captured length " + std::to_string(caplen) +
                                 " exceeds the packet block (" + std::to_string(length) +
                                 " bytes)");
            }
        }
        if (interface_id >= interfaces_.size()) {
            Fail(offset, "packet of interface " + std::to_string(interface_id) + ", but " +
                             std::to_string(interfaces_.size()) +
                             " interfaces are described in this section");
        }
        const Interface& itf = interfaces_[interface_id];
        if (type == kBlockSimplePacket && itf.snaplen != 0) caplen = std::min(caplen, itf.snaplen);
        if (caplen > PcapReader::kMaxCaptureBytes) {
            Fail(offset, "captured length " + std::to_string(caplen) + " exceeds " +
                             std::to_string(PcapReader::kMaxCaptureBytes));
        }
        // Simple packet blocks carry no timestamp.
        record.timestamp_ns = type == kBlockSimplePacket ? 0 : Time(itf, high, low, offset);
        record.link_type = itf.link_type;
        record.interface_id = interface_id;
        record.original_length = original;
        record.data = std::span<const uint8_t>(block + header, caplen);
        record.index = records;
        record.file_offset = offset;
        pos_ += length;
        return true;
    }
}

}  // namespace bimslam::net::detail
