// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/net/pcap_reader.hpp"

#include <pcap/pcap.h>
#include <stdio_ext.h>
#include <zlib.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

#include "algorithms/common/status.hpp"
#include "drivers/net/capture_file.hpp"
#include "drivers/net/pcapng_reader.hpp"

namespace bimslam::net {
namespace {

using common::FileError;
using common::StatusCode;

// Classic pcap magics as read in the file's own byte order (pcap-savefile(5)), and pcapng's
// section header block type (the same in both byte orders).
constexpr uint32_t kMagicMicroseconds = 0xA1B2C3D4;
constexpr uint32_t kMagicNanoseconds = 0xA1B23C4D;
constexpr uint32_t kMagicModified = 0xA1B2CD34;  // Kuznetsov's patched libpcap: 24-byte records
constexpr uint32_t kMagicPcapNg = 0x0A0D0D0A;
constexpr size_t kClassicFileHeaderBytes = 24;

uint32_t Load32(const uint8_t* p, bool swapped) {
    uint32_t v;
    std::memcpy(&v, p, 4);
    return swapped ? __builtin_bswap32(v) : v;
}

}  // namespace

struct PcapReader::State {
    std::string name;
    PcapFormat format = PcapFormat::kPcap;
    // Declared before what reads through it: destroyed after them.
    std::vector<char> stream_buffer;
    detail::FilePtr file;  // until libpcap takes it (pcap_close closes it)
    const detail::GzipStatus* gzip = nullptr;
    std::unique_ptr<detail::PcapNgReader> ng;

    // Classic pcap through libpcap.
    pcap_t* pcap = nullptr;
    FILE* pcap_file = nullptr;        // libpcap's input (owned by `pcap`), for ftell and feof
    const uint8_t* memory = nullptr;  // FromMemory: records point into the caller's bytes
    size_t record_header_bytes = 16;  // 24 for the modified format
    uint64_t position = kClassicFileHeaderBytes;  // file offset of the next record
    bool nanosecond = false;
    uint32_t link_type = 0;
    uint32_t snaplen = 0;
    uint32_t snapshot = 0;  // libpcap's snaplen (clamped to its maximum for the link type)

    uint64_t records = 0;
    bool truncated = false;
    uint64_t truncated_bytes = 0;
    bool done = false;

    ~State() {
        if (pcap != nullptr) pcap_close(pcap);
    }

    [[noreturn]] void Fail(uint64_t offset, const std::string& what) const {
        throw FileError(StatusCode::kParseError, name, 0,
                        "at byte " + std::to_string(offset) + ": " + what);
    }

    void Open();
    void OpenClassic(detail::FilePtr& stream, const uint8_t* header, size_t header_size);
    bool NextClassic(PcapRecord& record);
};

// Reads the first bytes to tell classic pcap from pcapng, then goes back to the start for the
// reader of the format.
void PcapReader::State::Open() {
    FILE* stream = file.get();
    uint8_t header[kClassicFileHeaderBytes] = {};
    const size_t got = std::fread(header, 1, sizeof(header), stream);
    if (std::ferror(stream) != 0) detail::ThrowReadError(name, gzip, 0, std::strerror(errno));
    if (std::fseek(stream, 0, SEEK_SET) != 0) {
        throw FileError(StatusCode::kIoError, name, 0,
                        std::string("cannot go back to the start: ") + std::strerror(errno));
    }
    if (got < 4) {
        throw FileError(
            StatusCode::kParseError, name, 0,
            "file holds " + std::to_string(got) + " bytes: too short for a pcap or pcapng header");
    }
    if (Load32(header, false) == kMagicPcapNg) {
        format = PcapFormat::kPcapNg;
        ng = std::make_unique<detail::PcapNgReader>(name, stream, gzip);
        return;
    }
    OpenClassic(file, header, got);
}

// Classic pcap (draft-ietf-opsawg-pcap; pcap-savefile(5)): libpcap reads it. libpcap's messages
// say what is wrong; where in the file follows from how far it read.
// On success libpcap owns `owner`'s stream.
void PcapReader::State::OpenClassic(detail::FilePtr& owner, const uint8_t* header,
                                    size_t header_size) {
    FILE* stream = owner.get();
    char error[PCAP_ERRBUF_SIZE] = {};
    pcap = pcap_fopen_offline_with_tstamp_precision(stream, PCAP_TSTAMP_PRECISION_NANO, error);
    if (pcap != nullptr) owner.release();  // pcap_close closes it
    if (pcap == nullptr) {
        const long at = std::ftell(stream);
        if (std::ferror(stream) != 0) detail::ThrowReadError(name, gzip, 0, error);
        const uint32_t magic = Load32(header, false);
        if (at == 4 && std::feof(stream) == 0) {
            char hex[16];
            std::snprintf(hex, sizeof(hex), "0x%08X", magic);
            const bool gz = (magic & 0xFFFF) == 0x8B1F;  // only FromMemory sees compressed bytes
            Fail(0, std::string("bad magic ") + hex +
                        (gz ? ": gzip data; open the file by its path to read it"
                            : ": not a pcap (A1B2C3D4, A1B23C4D) or pcapng file"));
        }
        if (header_size < kClassicFileHeaderBytes) {
            Fail(0, "file ends inside the 24-byte pcap file header (" +
                        std::to_string(header_size) + " bytes)");
        }
        // The whole header was read: libpcap refused its version (2.0 to 2.4 are read).
        Fail(4, std::string("unsupported pcap version: ") + error);
    }
    pcap_file = stream;
    snapshot = static_cast<uint32_t>(pcap_snapshot(pcap));
    // libpcap clamps the snapshot length to its maximum for the link type and maps the file's
    // link type (tcpdump.org/linktypes.html) to its own DLT_ numbers (101, raw IP, becomes
    // DLT_RAW 12); records carry the file's link type, and a snaplen above kMaxCaptureBytes is a
    // corrupt header, so both come from the header itself. The low 16 bits are the link type,
    // the upper ones FCS length flags (LT_LINKTYPE in libpcap's pcap-common.h).
    const bool swapped = pcap_is_swapped(pcap) == 1;
    const uint32_t magic = Load32(header, swapped);
    nanosecond = magic == kMagicNanoseconds;
    record_header_bytes = magic == kMagicModified ? 24 : 16;
    snaplen = Load32(header + 16, swapped);
    link_type = Load32(header + 20, swapped) & 0xFFFF;
    if (snaplen > kMaxCaptureBytes) {
        Fail(16, "snaplen " + std::to_string(snaplen) + " exceeds " +
                     std::to_string(kMaxCaptureBytes) + ": corrupt file header");
    }
}

bool PcapReader::State::NextClassic(PcapRecord& record) {
    pcap_pkthdr* header = nullptr;
    const u_char* bytes = nullptr;
    const int status = pcap_next_ex(pcap, &header, &bytes);
    const uint64_t start = position;
    if (status == 1) {
        // libpcap keeps the first `snaplen` bytes of a longer record and skips the rest: only
        // then does the record's size in the file differ from caplen (ftell costs a call).
        position = header->caplen < snapshot ? start + record_header_bytes + header->caplen
                                             : static_cast<uint64_t>(std::ftell(pcap_file));
        // ts_sec and the fraction are unsigned 32-bit fields (draft-ietf-opsawg-pcap) that
        // libpcap hands over sign-extended: ts_sec runs to 2106, well inside int64 nanoseconds.
        const auto seconds = static_cast<uint32_t>(header->ts.tv_sec);
        const int64_t fraction =
            nanosecond ? static_cast<uint32_t>(header->ts.tv_usec)
                       : int64_t{static_cast<uint32_t>(header->ts.tv_usec / 1000)} * 1000;
        record.timestamp_ns = int64_t{seconds} * 1'000'000'000 + fraction;
        record.link_type = link_type;
        record.interface_id = 0;
        record.original_length = header->len;
        // The bytes libpcap copied are the caller's own: FromMemory hands out those.
        record.data = std::span<const uint8_t>(
            memory != nullptr ? memory + start + record_header_bytes : bytes, header->caplen);
        record.index = records++;
        record.file_offset = start;
        return true;
    }
    done = true;
    if (status == PCAP_ERROR_BREAK) return false;  // the end, between two records
    if (std::ferror(pcap_file) != 0) detail::ThrowReadError(name, gzip, start, pcap_geterr(pcap));
    if (std::feof(pcap_file) != 0) {
        // The file ended inside the record: a killed capture, not an error.
        truncated = true;
        truncated_bytes = static_cast<uint64_t>(std::ftell(pcap_file)) - start;
        return false;
    }
    // Not the end of the file and not a read error: libpcap refused the record header, whose
    // captured length exceeds the snapshot length or libpcap's maximum for the link type.
    Fail(start, "record " + std::to_string(records) +
                    ": captured length out of range, corrupt record header (libpcap: " +
                    pcap_geterr(pcap) + ")");
}

PcapReader::PcapReader(std::unique_ptr<State> state) : state_(std::move(state)) {}

PcapReader::PcapReader(const std::filesystem::path& path) {
    auto state = std::make_unique<State>();
    state->name = path.string();
    const detail::CaptureFile input = detail::OpenCaptureFile(path, state->stream_buffer);
    state->file.reset(input.file);
    state->gzip = input.gzip;
    state->Open();
    state_ = std::move(state);
}

PcapReader PcapReader::FromMemory(std::string name, std::span<const uint8_t> bytes) {
    auto state = std::make_unique<State>();
    state->name = std::move(name);
    uint8_t header[kClassicFileHeaderBytes] = {};
    const size_t got = std::min(bytes.size(), sizeof(header));
    std::memcpy(header, bytes.data(), got);
    if (got >= 4 && Load32(header, false) == kMagicPcapNg) {
        state->format = PcapFormat::kPcapNg;
        state->ng = std::make_unique<detail::PcapNgReader>(state->name, bytes);
        return PcapReader(std::move(state));
    }
    if (got < 4) {
        throw FileError(
            StatusCode::kParseError, state->name, 0,
            "file holds " + std::to_string(got) + " bytes: too short for a pcap or pcapng header");
    }
    // libpcap reads a FILE*: fmemopen(3) over the caller's bytes (read-only: "r").
    FILE* stream = fmemopen(const_cast<uint8_t*>(bytes.data()), bytes.size(), "r");
    if (stream == nullptr) {
        throw FileError(StatusCode::kIoError, state->name, 0,
                        std::string("fmemopen: ") + std::strerror(errno));
    }
    detail::FilePtr owned(stream);
    __fsetlocking(stream, FSETLOCKING_BYCALLER);  // one reader: no lock per fread
    state->memory = bytes.data();
    state->OpenClassic(owned, header, got);
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
    State& s = *state_;
    if (s.ng != nullptr) {
        if (!s.ng->Next(record, s.records)) return false;
        ++s.records;
        return true;
    }
    return !s.done && s.NextClassic(record);
}

bool PcapReader::truncated() const {
    const State& s = *state_;
    if (s.ng != nullptr) return s.ng->truncated();
    return s.truncated || (s.done && s.gzip != nullptr && s.gzip->cut);
}
uint64_t PcapReader::truncated_bytes() const {
    return state_->ng != nullptr ? state_->ng->truncated_bytes() : state_->truncated_bytes;
}
uint64_t PcapReader::records() const { return state_->records; }
uint64_t PcapReader::skipped_blocks() const {
    return state_->ng != nullptr ? state_->ng->skipped_blocks() : 0;
}
PcapFormat PcapReader::format() const { return state_->format; }
uint32_t PcapReader::link_type() const {
    return state_->ng != nullptr ? state_->ng->link_type() : state_->link_type;
}
uint32_t PcapReader::snaplen() const {
    return state_->ng != nullptr ? state_->ng->snaplen() : state_->snaplen;
}
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
    for (uint32_t magic : {kMagicMicroseconds, kMagicNanoseconds}) {
        if (le == magic || be == magic) return true;
    }
    return le == kMagicPcapNg;
}

}  // namespace bimslam::net
