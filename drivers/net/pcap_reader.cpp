#include "drivers/net/pcap_reader.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

#include "algorithms/common/status.hpp"

namespace bimslam::net {
namespace {

using common::FileError;
using common::StatusCode;

// Classic pcap magics as read in the file's own byte order (pcap-savefile(5)).
constexpr uint32_t kMagicMicroseconds = 0xA1B2C3D4;
constexpr uint32_t kMagicNanoseconds = 0xA1B23C4D;
constexpr uint32_t kMagicModified = 0xA1B2CD34;  // Kuznetsov's patched libpcap; never supported
constexpr size_t kClassicFileHeaderBytes = 24;
constexpr size_t kClassicRecordHeaderBytes = 16;

// pcapng block types and the byte-order magic (draft-ietf-opsawg-pcapng, section 4).
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

// The file buffer holds the largest loaded block twice over, so a refill always makes room.
constexpr size_t kBufferBytes = 2 * static_cast<size_t>(PcapReader::kMaxLoadedBlockBytes);

// pcapng timestamps are 64-bit counts of 10^-n or 2^-n seconds: the conversion to nanoseconds
// needs 128-bit intermediates (a GCC/Clang extension).
__extension__ typedef __int128 Int128;
__extension__ typedef unsigned __int128 UInt128;

uint32_t Swap32(uint32_t v) { return __builtin_bswap32(v); }

}  // namespace

struct PcapReader::State {
    // A pcapng Interface Description Block, as far as reading packets needs it.
    struct Interface {
        uint32_t link_type = 0;
        uint32_t snaplen = 0;
        uint8_t tsresol = 6;  // if_tsresol: default 10^-6 s
        int64_t tsoffset_s = 0;
    };

    std::string name;
    // Input: either a gzip/plain file through zlib into `buffer`, or the caller's memory.
    gzFile gz = nullptr;
    std::vector<uint8_t> buffer;
    const uint8_t* data = nullptr;
    size_t size = 0;           // valid bytes at data
    size_t pos = 0;            // next unread byte at data
    uint64_t data_offset = 0;  // file offset of data[0]
    bool eof = false;

    PcapFormat format = PcapFormat::kPcap;
    bool swapped = false;  // the file's byte order differs from this host's (little-endian)
    bool nanosecond = false;
    uint32_t link_type = 0;
    uint32_t snaplen = 0;
    std::vector<Interface> interfaces;  // pcapng, current section

    uint64_t records = 0;
    uint64_t skipped_blocks = 0;
    bool truncated = false;
    uint64_t truncated_bytes = 0;
    bool done = false;

    ~State() {
        if (gz != nullptr) gzclose(gz);
    }

    uint64_t Offset() const { return data_offset + pos; }
    size_t Available() const { return size - pos; }

    [[noreturn]] void Fail(uint64_t offset, const std::string& what) const {
        throw FileError(StatusCode::kParseError, name, 0,
                        "at byte " + std::to_string(offset) + ": " + what);
    }

    uint16_t U16(const uint8_t* p) const {
        uint16_t v;
        std::memcpy(&v, p, 2);
        return swapped ? static_cast<uint16_t>((v >> 8) | (v << 8)) : v;
    }
    uint32_t U32(const uint8_t* p) const {
        uint32_t v;
        std::memcpy(&v, p, 4);
        return swapped ? Swap32(v) : v;
    }

    // Makes `n` (<= kBufferBytes / 2) bytes available at data + pos, reading more of the file when
    // needed; false when the file ends first.
    bool Ensure(size_t n) {
        if (Available() >= n) return true;
        if (gz == nullptr || eof) return false;
        std::memmove(buffer.data(), buffer.data() + pos, Available());
        data_offset += pos;
        size -= pos;
        pos = 0;
        while (size < n && !eof) {
            const unsigned want = static_cast<unsigned>(buffer.size() - size);
            const int got = gzread(gz, buffer.data() + size, want);
            if (got < 0) ReadError();
            if (got == 0) {
                eof = true;
                // zlib reports a gzip stream cut off before its trailer as Z_BUF_ERROR and returns
                // what it could decompress: the same as a killed capture.
                int code = Z_OK;
                gzerror(gz, &code);
                if (code == Z_BUF_ERROR) truncated = true;
            }
            size += static_cast<size_t>(std::max(got, 0));
        }
        return size >= n;
    }

    [[noreturn]] void ReadError() const {
        int code = Z_OK;
        const char* message = gzerror(gz, &code);
        if (code == Z_ERRNO) {
            throw FileError(StatusCode::kIoError, name, 0,
                            "read failed after byte " + std::to_string(data_offset + size) + ": " +
                                std::strerror(errno));
        }
        throw FileError(StatusCode::kParseError, name, 0,
                        "gzip data broken after byte " + std::to_string(data_offset + size) +
                            " (decompressed): " + (message ? message : "unknown zlib error"));
    }

    // Skips `n` bytes; false when the file ends first.
    bool Skip(uint64_t n) {
        while (n > 0) {
            if (Available() == 0 && !Ensure(1)) return false;
            const size_t step = static_cast<size_t>(std::min<uint64_t>(n, Available()));
            pos += step;
            n -= step;
        }
        return true;
    }

    // The file ended inside a record that starts at the current position.
    bool EndTruncated() {
        truncated = true;
        truncated_bytes = Available();
        pos = size;
        done = true;
        return false;
    }

    // Sets the byte order from the magic of the section header block at data + pos.
    void ReadByteOrder(uint64_t offset) {
        uint32_t bom;
        std::memcpy(&bom, data + pos + 8, 4);
        if (bom == kByteOrderMagic) {
            swapped = false;
        } else if (bom == Swap32(kByteOrderMagic)) {
            swapped = true;
        } else {
            char hex[16];
            std::snprintf(hex, sizeof(hex), "0x%08X", bom);
            Fail(offset + 8, std::string("bad pcapng byte-order magic ") + hex);
        }
    }

    // A block repeats its length at its end.
    void CheckTrailer(const uint8_t* block, uint32_t length, uint64_t offset) const {
        const uint32_t trailer = U32(block + length - 4);
        if (trailer != length) {
            Fail(offset, "block length " + std::to_string(length) + " at the start, " +
                             std::to_string(trailer) + " at the end");
        }
    }

    void ReadFileHeader();
    void ReadClassicHeader(uint32_t magic);
    bool NextClassic(PcapRecord& record);
    bool NextPcapNg(PcapRecord& record);
    void ReadSectionHeader(const uint8_t* block, uint32_t length, uint64_t offset);
    void ReadInterface(const uint8_t* block, uint32_t length, uint64_t offset);
    int64_t PcapNgTime(const Interface& itf, uint32_t high, uint32_t low, uint64_t offset) const;
};

void PcapReader::State::ReadFileHeader() {
    if (!Ensure(4)) {
        throw FileError(StatusCode::kParseError, name, 0,
                        "file holds " + std::to_string(Available()) +
                            " bytes: too short for a pcap or pcapng header");
    }
    uint32_t magic;
    std::memcpy(&magic, data + pos, 4);
    if (magic == kBlockSectionHeader) {
        // The first block must be a complete section header: unlike a later block that the file
        // ends in, a broken one here is an error, not a truncated capture.
        format = PcapFormat::kPcapNg;
        if (!Ensure(12)) Fail(0, "file ends inside the pcapng section header block");
        ReadByteOrder(0);
        const uint32_t length = U32(data + pos + 4);
        if (length < 28 || length % 4 != 0 || length > kMaxLoadedBlockBytes) {
            Fail(4, "bad section header block length " + std::to_string(length));
        }
        if (!Ensure(length)) {
            Fail(0, "file ends inside the pcapng section header block (" +
                        std::to_string(Available()) + " of " + std::to_string(length) + " bytes)");
        }
        CheckTrailer(data + pos, length, 0);
        ReadSectionHeader(data + pos, length, 0);
        pos += length;
        // The interface blocks that follow (libpcap, dumpcap and Wireshark write them before any
        // packet) give link_type() before the first record; anything else is left to Next().
        while (Ensure(8) && U32(data + pos) == kBlockInterfaceDescription) {
            const uint64_t offset = Offset();
            const uint32_t block_length = U32(data + pos + 4);
            if (block_length < 20 || block_length % 4 != 0 || block_length > kMaxLoadedBlockBytes ||
                !Ensure(block_length)) {
                break;
            }
            CheckTrailer(data + pos, block_length, offset);
            ReadInterface(data + pos, block_length, offset);
            pos += block_length;
        }
        return;
    }
    ReadClassicHeader(magic);
}

void PcapReader::State::ReadClassicHeader(uint32_t magic) {
    if (magic == kMagicMicroseconds || magic == kMagicNanoseconds) {
        swapped = false;
    } else if (Swap32(magic) == kMagicMicroseconds || Swap32(magic) == kMagicNanoseconds) {
        swapped = true;
        magic = Swap32(magic);
    } else if (magic == kMagicModified || Swap32(magic) == kMagicModified) {
        Fail(0, "modified (Kuznetsov) pcap format is not supported; convert it with editcap");
    } else {
        char hex[16];
        std::snprintf(hex, sizeof(hex), "0x%08X", magic);
        const bool gzip = (magic & 0xFFFF) == 0x8B1F;  // only FromMemory sees compressed bytes
        Fail(0, std::string("bad magic ") + hex +
                    (gzip ? ": gzip data; open the file by its path to read it"
                          : ": not a pcap (A1B2C3D4, A1B23C4D) or pcapng file"));
    }
    format = PcapFormat::kPcap;
    nanosecond = magic == kMagicNanoseconds;
    if (!Ensure(kClassicFileHeaderBytes)) {
        Fail(0, "file ends inside the 24-byte pcap file header (" + std::to_string(Available()) +
                    " bytes)");
    }
    const uint8_t* h = data + pos;
    const uint16_t major = U16(h + 4);
    const uint16_t minor = U16(h + 6);
    if (major != 2) {
        Fail(4, "unsupported pcap version " + std::to_string(major) + "." + std::to_string(minor) +
                    " (only 2.x)");
    }
    snaplen = U32(h + 16);
    if (snaplen > kMaxCaptureBytes) {
        Fail(16, "snaplen " + std::to_string(snaplen) + " exceeds " +
                     std::to_string(kMaxCaptureBytes) + ": corrupt file header");
    }
    // The low 16 bits are the link type; the upper ones carry FCS length flags (LT_LINKTYPE in
    // libpcap's pcap-common.h).
    link_type = U32(h + 20) & 0xFFFF;
    pos += kClassicFileHeaderBytes;
}

bool PcapReader::State::NextClassic(PcapRecord& record) {
    if (!Ensure(kClassicRecordHeaderBytes)) {
        if (Available() == 0) {
            done = true;
            return false;
        }
        return EndTruncated();
    }
    const uint64_t offset = Offset();
    const uint8_t* h = data + pos;
    const uint32_t seconds = U32(h);
    const uint32_t fraction = U32(h + 4);
    const uint32_t caplen = U32(h + 8);
    const uint32_t length = U32(h + 12);
    if (caplen > kMaxCaptureBytes) {
        Fail(offset, "record " + std::to_string(records) + ": captured length " +
                         std::to_string(caplen) + " exceeds " + std::to_string(kMaxCaptureBytes) +
                         ": corrupt record header");
    }
    if (!Ensure(kClassicRecordHeaderBytes + caplen)) return EndTruncated();
    // ts_sec is unsigned (draft-ietf-opsawg-pcap): up to 2106, well inside int64 nanoseconds.
    record.timestamp_ns = static_cast<int64_t>(seconds) * 1'000'000'000 +
                          static_cast<int64_t>(fraction) * (nanosecond ? 1 : 1000);
    record.link_type = link_type;
    record.interface_id = 0;
    record.original_length = length;
    record.data = std::span<const uint8_t>(data + pos + kClassicRecordHeaderBytes, caplen);
    record.index = records++;
    record.file_offset = offset;
    pos += kClassicRecordHeaderBytes + caplen;
    return true;
}

int64_t PcapReader::State::PcapNgTime(const Interface& itf, uint32_t high, uint32_t low,
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

void PcapReader::State::ReadSectionHeader(const uint8_t* block, uint32_t length, uint64_t offset) {
    if (length < 28)
        Fail(offset, "section header block length " + std::to_string(length) + " < 28");
    const uint16_t major = U16(block + 12);
    if (major != 1) {
        Fail(offset + 12, "unsupported pcapng version " + std::to_string(major) + "." +
                              std::to_string(U16(block + 14)) + " (only 1.x)");
    }
    interfaces.clear();  // interface ids are per section
}

void PcapReader::State::ReadInterface(const uint8_t* block, uint32_t length, uint64_t offset) {
    if (length < 20) {
        Fail(offset, "interface description block length " + std::to_string(length) + " < 20");
    }
    if (interfaces.size() >= kMaxInterfaces) {
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
                static_cast<int64_t>(swapped ? (first << 32) | second : (second << 32) | first);
        }
        at += 4 + padded;
    }
    if (interfaces.empty()) {
        link_type = itf.link_type;
        snaplen = itf.snaplen;
    }
    interfaces.push_back(itf);
}

bool PcapReader::State::NextPcapNg(PcapRecord& record) {
    for (;;) {
        if (!Ensure(8)) {
            if (Available() == 0) {
                done = true;
                return false;
            }
            return EndTruncated();
        }
        const uint64_t offset = Offset();
        uint32_t type;
        std::memcpy(&type, data + pos, 4);
        if (type == kBlockSectionHeader) {
            // A new section may switch the byte order: read it from the byte-order magic.
            if (!Ensure(12)) return EndTruncated();
            ReadByteOrder(offset);
        } else {
            type = U32(data + pos);
        }
        const uint32_t length = U32(data + pos + 4);
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
            if (U32(data + pos) != length) {
                Fail(offset, "block length " + std::to_string(length) + " at the start, " +
                                 std::to_string(U32(data + pos)) + " at the end");
            }
            pos += 4;
            ++skipped_blocks;
            continue;
        }
        if (length > kMaxLoadedBlockBytes) {
            Fail(offset, "block length " + std::to_string(length) + " (block type " +
                             std::to_string(type) + ") exceeds " +
                             std::to_string(kMaxLoadedBlockBytes));
        }
        if (!Ensure(length)) return EndTruncated();
        const uint8_t* block = data + pos;
        CheckTrailer(block, length, offset);
        if (type == kBlockSectionHeader) {
            ReadSectionHeader(block, length, offset);
            pos += length;
            continue;
        }
        if (type == kBlockInterfaceDescription) {
            ReadInterface(block, length, offset);
            pos += length;
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
        if (interface_id >= interfaces.size()) {
            Fail(offset, "packet of interface " + std::to_string(interface_id) + ", but " +
                             std::to_string(interfaces.size()) +
                             " interfaces are described in this section");
        }
        const Interface& itf = interfaces[interface_id];
        if (type == kBlockSimplePacket && itf.snaplen != 0) caplen = std::min(caplen, itf.snaplen);
        if (caplen > kMaxCaptureBytes) {
            Fail(offset, "captured length " + std::to_string(caplen) + " exceeds " +
                             std::to_string(kMaxCaptureBytes));
        }
        // Simple packet blocks carry no timestamp.
        record.timestamp_ns = type == kBlockSimplePacket ? 0 : PcapNgTime(itf, high, low, offset);
        record.link_type = itf.link_type;
        record.interface_id = interface_id;
        record.original_length = original;
        record.data = std::span<const uint8_t>(block + header, caplen);
        record.index = records++;
        record.file_offset = offset;
        pos += length;
        return true;
    }
}

PcapReader::PcapReader(std::unique_ptr<State> state) : state_(std::move(state)) {
    state_->ReadFileHeader();
}

PcapReader::PcapReader(const std::filesystem::path& path) {
    auto state = std::make_unique<State>();
    state->name = path.string();
    // open() first so that errno names the reason; zlib reads plain files as they are.
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        const int err = errno;
        throw FileError(err == ENOENT ? StatusCode::kNotFound : StatusCode::kIoError, state->name,
                        0, std::string("cannot open: ") + std::strerror(err));
    }
    state->gz = gzdopen(fd, "rb");
    if (state->gz == nullptr) {
        ::close(fd);
        throw FileError(StatusCode::kIoError, state->name, 0, "cannot open (zlib)");
    }
    gzbuffer(state->gz, 256 * 1024);
    state->buffer.resize(kBufferBytes);
    state->data = state->buffer.data();
    state_ = std::move(state);
    state_->ReadFileHeader();
}

PcapReader PcapReader::FromMemory(std::string name, std::span<const uint8_t> bytes) {
    auto state = std::make_unique<State>();
    state->name = std::move(name);
    state->data = bytes.data();
    state->size = bytes.size();
    state->eof = true;
    return PcapReader(std::move(state));
}

PcapReader PcapReader::FromMemory(std::string name, std::string_view bytes) {
    return FromMemory(
        std::move(name),
        std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()));
}

PcapReader::PcapReader(PcapReader&&) noexcept = default;
PcapReader& PcapReader::operator=(PcapReader&&) noexcept = default;
PcapReader::~PcapReader() = default;

bool PcapReader::Next(PcapRecord& record) {
    if (state_->done) return false;
    return state_->format == PcapFormat::kPcap ? state_->NextClassic(record)
                                               : state_->NextPcapNg(record);
}

bool PcapReader::truncated() const { return state_->truncated; }
uint64_t PcapReader::truncated_bytes() const { return state_->truncated_bytes; }
uint64_t PcapReader::records() const { return state_->records; }
uint64_t PcapReader::skipped_blocks() const { return state_->skipped_blocks; }
PcapFormat PcapReader::format() const { return state_->format; }
uint32_t PcapReader::link_type() const { return state_->link_type; }
uint32_t PcapReader::snaplen() const { return state_->snaplen; }
bool PcapReader::nanosecond() const { return state_->nanosecond; }
const std::string& PcapReader::name() const { return state_->name; }

bool LooksLikePcap(const std::filesystem::path& path) {
    uint8_t h[4] = {};
    gzFile f = gzopen(path.c_str(), "rb");
    if (f == nullptr) return false;
    const int n = gzread(f, h, sizeof(h));
    gzclose(f);
    if (n != 4) return false;
    const uint32_t le = h[0] | h[1] << 8 | h[2] << 16 | uint32_t(h[3]) << 24;
    const uint32_t be = h[3] | h[2] << 8 | h[1] << 16 | uint32_t(h[0]) << 24;
    for (uint32_t magic : {0xA1B2C3D4u, 0xA1B23C4Du}) {
        if (le == magic || be == magic) return true;
    }
    return le == 0x0A0D0D0Au;  // pcapng section header (the same in both byte orders)
}

}  // namespace bimslam::net
