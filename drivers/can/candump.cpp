// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/can/candump.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <limits>
#include <vector>

#include "algorithms/common/status.hpp"

namespace bimslam::can {
namespace {

using common::CanFrame;
using common::Error;
using common::FileError;
using common::StatusCode;

constexpr size_t kMinBufferBytes = 64 * 1024;
constexpr size_t kMaxInterfaceChars = 15;  // IFNAMSIZ - 1
constexpr int64_t kNsPerSecond = 1'000'000'000;

int HexValue(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    return -1;
}

bool IsSpace(char c) { return c == ' ' || c == '\t'; }

// "<digits>.<1..9 digits>" exactly into nanoseconds.
bool ParseTimestamp(std::string_view text, int64_t& ns, std::string_view& what) {
    const size_t dot = text.find('.');
    if (dot == std::string_view::npos) {
        what = "timestamp without a '.' between seconds and fraction";
        return false;
    }
    const std::string_view seconds = text.substr(0, dot);
    const std::string_view fraction = text.substr(dot + 1);
    if (seconds.empty() || fraction.empty()) {
        what = "timestamp without digits before or after the '.'";
        return false;
    }
    if (fraction.size() > 9) {
        what = "timestamp with more than 9 fraction digits (finer than a nanosecond)";
        return false;
    }
    constexpr int64_t kMaxSeconds = std::numeric_limits<int64_t>::max() / kNsPerSecond;
    int64_t s = 0;
    for (char c : seconds) {
        if (c < '0' || c > '9') {
            what = "timestamp seconds that are not decimal digits";
            return false;
        }
        s = s * 10 + (c - '0');
        if (s > kMaxSeconds) {
            what = "timestamp beyond the int64 nanosecond range";
            return false;
        }
    }
    int64_t f = 0;
    for (char c : fraction) {
        if (c < '0' || c > '9') {
            what = "timestamp fraction that is not decimal digits";
            return false;
        }
        f = f * 10 + (c - '0');
    }
    for (size_t i = fraction.size(); i < 9; ++i) f *= 10;
    if (s == kMaxSeconds && f > std::numeric_limits<int64_t>::max() - s * kNsPerSecond) {
        what = "timestamp beyond the int64 nanosecond range";
        return false;
    }
    ns = s * kNsPerSecond + f;
    return true;
}

// The frame text after "<id>#": data, FD, remote. `frame` holds the id already.
bool ParseFrameBody(std::string_view body, CanFrame& frame, CandumpIssue& issue,
                    std::string_view& what) {
    size_t i = 0;
    if (!body.empty() && (body[0] == 'R' || body[0] == 'r')) {
        if (frame.error) {
            issue = CandumpIssue::kBadId;
            what = "error flag in the id of a remote frame";
            return false;
        }
        frame.remote = true;
        i = 1;
        if (i < body.size() && body[i] != '_') {
            const int dlc = HexValue(body[i]);
            if (dlc < 0) {
                issue = CandumpIssue::kNonHex;
                what = "remote frame DLC that is not a hex digit";
                return false;
            }
            if (dlc > 8) {
                issue = CandumpIssue::kBadLength;
                what = "remote frame DLC above 8";
                return false;
            }
            frame.len = static_cast<uint8_t>(dlc);
            ++i;
        }
    } else if (!body.empty() && body[0] == '#') {
        if (frame.error) {
            issue = CandumpIssue::kBadId;
            what = "error flag in the id of a CAN FD frame";
            return false;
        }
        if (body.size() < 2) {
            issue = CandumpIssue::kGarbage;
            what = "no flags digit after '##' (CAN FD)";
            return false;
        }
        const int flags = HexValue(body[1]);
        if (flags < 0) {
            issue = CandumpIssue::kNonHex;
            what = "CAN FD flags that are not a hex digit";
            return false;
        }
        frame.fd = true;
        frame.fd_flags = static_cast<uint8_t>(flags);
        i = 2;
    }
    if (!frame.remote) {
        // Data: hex digit pairs, optionally '.' between bytes.
        size_t digits = 0;
        size_t bytes = 0;
        bool too_many = false;
        const size_t max_bytes = frame.fd ? 64 : 8;
        for (; i < body.size() && body[i] != '_'; ++i) {
            const char c = body[i];
            if (c == '.' && digits % 2 == 0) continue;
            const int v = HexValue(c);
            if (v < 0) {
                issue = CandumpIssue::kNonHex;
                what = c == '.' ? "'.' inside a data byte" : "data that is not hex digits";
                return false;
            }
            if (digits % 2 == 0) {
                if (bytes == max_bytes) too_many = true;
                if (!too_many) frame.data[bytes] = static_cast<uint8_t>(v << 4);
            } else {
                if (!too_many) frame.data[bytes] |= static_cast<uint8_t>(v);
                ++bytes;
            }
            ++digits;
        }
        if (digits % 2 != 0) {
            issue = CandumpIssue::kOddHex;
            what = "data with an odd number of hex digits";
            return false;
        }
        if (too_many) {
            issue = CandumpIssue::kBadLength;
            what = frame.fd ? "CAN FD frame with more than 64 data bytes"
                            : "classic CAN frame with more than 8 data bytes";
            return false;
        }
        if (frame.fd && !common::IsCanFdLength(static_cast<unsigned>(bytes))) {
            issue = CandumpIssue::kBadLength;
            what = "CAN FD data length that no DLC gives (valid: 0-8, 12, 16, 20, 24, 32, 48, 64)";
            return false;
        }
        frame.len = static_cast<uint8_t>(bytes);
    }
    if (i < body.size()) {
        // "_<raw DLC>" after exactly 8 classic bytes (or a remote DLC of 8).
        if (body[i] != '_') {
            issue = CandumpIssue::kGarbage;
            what = "text after the remote frame's DLC";
            return false;
        }
        if (frame.fd || frame.len != 8 || i + 2 != body.size()) {
            issue = CandumpIssue::kBadLength;
            what = "raw DLC '_<9..F>' other than after 8 classic data bytes or a remote DLC of 8";
            return false;
        }
        const int dlc = HexValue(body[i + 1]);
        if (dlc < 9) {
            issue = dlc < 0 ? CandumpIssue::kNonHex : CandumpIssue::kBadLength;
            what = "raw DLC other than 9..F";
            return false;
        }
        frame.len8_dlc = static_cast<uint8_t>(dlc);
    }
    return true;
}

bool ParseFrame(std::string_view text, CanFrame& frame, CandumpIssue& issue,
                std::string_view& what) {
    if (text.find("###") != std::string_view::npos) {
        issue = CandumpIssue::kUnsupported;
        what = "CAN XL frame (not supported)";
        return false;
    }
    const size_t hash = text.find('#');
    if (hash == std::string_view::npos) {
        issue = CandumpIssue::kGarbage;
        what = "frame without '#' between id and data";
        return false;
    }
    const std::string_view id_text = text.substr(0, hash);
    if (id_text.size() != 3 && id_text.size() != 8) {
        issue = CandumpIssue::kBadId;
        what = "id of other than 3 (standard) or 8 (extended) hex digits";
        return false;
    }
    uint32_t id = 0;
    for (char c : id_text) {
        const int v = HexValue(c);
        if (v < 0) {
            issue = CandumpIssue::kBadId;
            what = "id that is not hex digits";
            return false;
        }
        id = (id << 4) | static_cast<uint32_t>(v);
    }
    if (id_text.size() == 3) {
        if (id > common::kCanSffMask) {
            issue = CandumpIssue::kBadId;
            what = "standard id above 7FF";
            return false;
        }
    } else if (id & common::kCanErrFlag) {
        if (id & (common::kCanEffFlag | common::kCanRtrFlag)) {
            issue = CandumpIssue::kBadId;
            what = "error frame id with the EFF or RTR flag bit";
            return false;
        }
        frame.error = true;
        id &= common::kCanEffMask;
    } else if (id > common::kCanEffMask) {
        issue = CandumpIssue::kBadId;
        what = "extended id above 1FFFFFFF (flag bits in the id)";
        return false;
    } else {
        frame.extended = true;
    }
    frame.id = id;
    return ParseFrameBody(text.substr(hash + 1), frame, issue, what);
}

// Splits off the next whitespace-separated token of `rest`.
std::string_view NextToken(std::string_view& rest) {
    size_t i = 0;
    while (i < rest.size() && IsSpace(rest[i])) ++i;
    size_t j = i;
    while (j < rest.size() && !IsSpace(rest[j])) ++j;
    const std::string_view token = rest.substr(i, j - i);
    rest.remove_prefix(j);
    return token;
}

bool IsDirection(std::string_view token) { return token == "R" || token == "T"; }

const char* InterfaceProblem(std::string_view name) {
    if (name.empty()) return "empty interface name";
    if (name.size() > kMaxInterfaceChars) return "interface name longer than 15 characters";
    for (char c : name) {
        if (static_cast<unsigned char>(c) <= ' ' || c == '\x7f') {
            return "interface name with white space or control characters";
        }
    }
    return nullptr;
}

// What FormatCandumpLine refuses, or nullptr.
const char* LineProblem(const CanFrame& frame, std::string_view interface_name) {
    if (const char* p = common::CanFrameProblem(frame)) return p;
    if (frame.timestamp_ns < 0) return "negative timestamp";
    return InterfaceProblem(interface_name);
}

// The line for a message: control characters replaced, long lines cut.
std::string Excerpt(std::string_view line) {
    constexpr size_t kMax = 160;
    std::string out;
    for (size_t i = 0; i < line.size() && i < kMax; ++i) {
        const unsigned char c = static_cast<unsigned char>(line[i]);
        out += (c < 0x20 || c >= 0x7f) ? '?' : static_cast<char>(c);
    }
    if (line.size() > kMax) out += "...";
    return out;
}

}  // namespace

std::string_view ToString(CandumpIssue issue) {
    switch (issue) {
        case CandumpIssue::kGarbage:
            return "garbage";
        case CandumpIssue::kBadTimestamp:
            return "bad timestamp";
        case CandumpIssue::kMissingInterface:
            return "missing interface";
        case CandumpIssue::kBadId:
            return "bad id";
        case CandumpIssue::kNonHex:
            return "non-hex";
        case CandumpIssue::kOddHex:
            return "odd hex digits";
        case CandumpIssue::kBadLength:
            return "bad length";
        case CandumpIssue::kBackwards:
            return "time going backwards";
        case CandumpIssue::kTooLong:
            return "line too long";
        case CandumpIssue::kUnsupported:
            return "unsupported (CAN XL)";
    }
    return "unknown";
}

bool ParseCandumpLine(std::string_view line, CandumpLine& out, CandumpIssue& issue,
                      std::string_view& what) {
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    size_t i = 0;
    while (i < line.size() && IsSpace(line[i])) ++i;
    if (i == line.size() || line[i] != '(') {
        issue = CandumpIssue::kGarbage;
        what = "line does not start with '(' and a timestamp";
        return false;
    }
    const size_t close = line.find(')', i);
    if (close == std::string_view::npos) {
        issue = CandumpIssue::kBadTimestamp;
        what = "timestamp without its closing ')'";
        return false;
    }
    out.frame = CanFrame{};
    if (!ParseTimestamp(line.substr(i + 1, close - i - 1), out.frame.timestamp_ns, what)) {
        issue = CandumpIssue::kBadTimestamp;
        return false;
    }
    std::string_view rest = line.substr(close + 1);
    if (!rest.empty() && !IsSpace(rest[0])) {
        issue = CandumpIssue::kGarbage;
        what = "no space after the timestamp";
        return false;
    }
    const std::string_view first = NextToken(rest);
    const std::string_view second = NextToken(rest);
    const std::string_view third = NextToken(rest);
    if (first.empty()) {
        issue = CandumpIssue::kGarbage;
        what = "nothing after the timestamp";
        return false;
    }
    const bool first_is_frame = first.find('#') != std::string_view::npos;
    if (first_is_frame && (second.empty() || (IsDirection(second) && third.empty()))) {
        issue = CandumpIssue::kMissingInterface;
        what = "no interface name between the timestamp and the frame";
        return false;
    }
    if (second.empty()) {
        issue = CandumpIssue::kGarbage;
        what = "no frame after the interface name";
        return false;
    }
    if (!NextToken(rest).empty() || (!third.empty() && !IsDirection(third))) {
        issue = CandumpIssue::kGarbage;
        what = "text after the frame";
        return false;
    }
    if (const char* p = InterfaceProblem(first)) {
        issue = CandumpIssue::kMissingInterface;
        what = p;
        return false;
    }
    out.interface_name = first;
    return ParseFrame(second, out.frame, issue, what);
}

size_t FormatCandumpLine(const CanFrame& frame, std::string_view interface_name,
                         std::span<char> out, int seconds_width, int interface_width) {
    if (out.size() < kMaxCandumpLineBytes || LineProblem(frame, interface_name) != nullptr) {
        return 0;
    }
    static constexpr char kHex[] = "0123456789ABCDEF";
    char* p = out.data();
    *p++ = '(';
    // Seconds, zero-padded to seconds_width (at most 20 digits).
    char digits[20];
    int n = 0;
    int64_t seconds = frame.timestamp_ns / kNsPerSecond;
    do {
        digits[n++] = static_cast<char>('0' + seconds % 10);
        seconds /= 10;
    } while (seconds > 0);
    for (int k = n; k < std::clamp(seconds_width, 1, 20); ++k) *p++ = '0';
    while (n > 0) *p++ = digits[--n];
    *p++ = '.';
    int64_t micros = (frame.timestamp_ns % kNsPerSecond) / 1000;
    for (int k = 5; k >= 0; --k) {
        p[k] = static_cast<char>('0' + micros % 10);
        micros /= 10;
    }
    p += 6;
    *p++ = ')';
    *p++ = ' ';
    for (int k = static_cast<int>(interface_name.size()); k < std::min(interface_width, 15); ++k) {
        *p++ = ' ';
    }
    std::memcpy(p, interface_name.data(), interface_name.size());
    p += interface_name.size();
    *p++ = ' ';
    const bool eight = frame.extended || frame.error;
    const uint32_t id = frame.error ? (frame.id | common::kCanErrFlag) : frame.id;
    for (int k = eight ? 7 : 2; k >= 0; --k) *p++ = kHex[(id >> (4 * k)) & 0xF];
    *p++ = '#';
    if (frame.remote) {
        *p++ = 'R';
        if (frame.len > 0) *p++ = kHex[frame.len];
    } else {
        if (frame.fd) {
            *p++ = '#';
            *p++ = kHex[frame.fd_flags & 0xF];
        }
        for (size_t k = 0; k < frame.len; ++k) {
            *p++ = kHex[frame.data[k] >> 4];
            *p++ = kHex[frame.data[k] & 0xF];
        }
    }
    if (frame.len8_dlc != 0) {
        *p++ = '_';
        *p++ = kHex[frame.len8_dlc & 0xF];
    }
    *p++ = '\n';
    return static_cast<size_t>(p - out.data());
}

// ---------------------------------------------------------------------------------------------
// Reader

void CandumpReaderConfig::Validate() const {
    if (max_line_bytes < kMaxCandumpLineBytes || max_line_bytes > (size_t{1} << 20)) {
        throw Error(StatusCode::kInvalidArgument,
                    "max_line_bytes: " + std::to_string(max_line_bytes) + ", must be in [" +
                        std::to_string(kMaxCandumpLineBytes) + ", 1048576]");
    }
    if (mode != CandumpMode::kStrict && mode != CandumpMode::kLenient) {
        throw Error(StatusCode::kInvalidArgument, "mode: not kStrict or kLenient");
    }
}

uint64_t CandumpStats::skipped_lines() const {
    uint64_t total = 0;
    for (uint64_t n : skipped) total += n;
    return total;
}

struct CandumpReader::State {
    std::string name;
    CandumpReaderConfig config;
    gzFile gz = nullptr;
    std::vector<char> buffer;
    const char* data = nullptr;
    size_t size = 0;
    size_t pos = 0;
    bool eof = false;
    bool truncated = false;
    uint64_t line = 0;
    bool have_last = false;
    int64_t last_ns = 0;
    CandumpStats stats;
    char excerpt[160];  // the start of a line too long to hold

    ~State() {
        if (gz != nullptr) gzclose(gz);
    }

    [[noreturn]] void ReadError() const {
        int code = Z_OK;
        const char* message = gzerror(gz, &code);
        if (code == Z_ERRNO) {
            throw FileError(StatusCode::kIoError, name, line + 1,
                            std::string("read failed: ") + std::strerror(errno));
        }
        throw FileError(StatusCode::kParseError, name, line + 1,
                        std::string("gzip data broken: ") +
                            (message != nullptr ? message : "unknown zlib error"));
    }

    // Moves the unread bytes to the front and reads more; false when nothing more came.
    bool Refill() {
        if (gz == nullptr || eof) return false;
        const size_t keep = size - pos;
        std::memmove(buffer.data(), buffer.data() + pos, keep);
        size = keep;
        pos = 0;
        const size_t before = size;
        while (size < buffer.size() && !eof) {
            const int got =
                gzread(gz, buffer.data() + size, static_cast<unsigned>(buffer.size() - size));
            if (got < 0) ReadError();
            if (got == 0) {
                eof = true;
                // A gzip stream cut before its trailer: zlib returns what it could decompress and
                // reports Z_BUF_ERROR, the same as a killed recording.
                int code = Z_OK;
                gzerror(gz, &code);
                if (code == Z_BUF_ERROR) truncated = true;
            }
            size += static_cast<size_t>(std::max(got, 0));
            if (std::memchr(buffer.data() + before, '\n', size - before) != nullptr) break;
        }
        return size > before;
    }

    enum class LineKind : uint8_t { kLine, kTooLong, kEnd };

    LineKind NextLine(std::string_view& out, bool& terminated) {
        const size_t max_line = config.max_line_bytes;
        for (;;) {
            const char* start = data + pos;
            const size_t available = size - pos;
            const size_t window = std::min(available, max_line + 1);
            const void* newline = std::memchr(start, '\n', window);
            if (newline != nullptr) {
                const size_t length =
                    static_cast<size_t>(static_cast<const char*>(newline) - start);
                out = std::string_view(start, length);
                pos += length + 1;
                terminated = true;
                return LineKind::kLine;
            }
            if (available > max_line) {
                // Too long: dropped up to its end, never held whole; its start kept for messages.
                const size_t kept = std::min(available, sizeof(excerpt));
                std::memcpy(excerpt, start, kept);
                out = std::string_view(excerpt, kept);
                SkipPastNewline();
                return LineKind::kTooLong;
            }
            if (!Refill()) {
                if (available == 0) return LineKind::kEnd;
                out = std::string_view(start, available);
                pos = size;
                terminated = false;
                return LineKind::kLine;
            }
        }
    }

    void SkipPastNewline() {
        for (;;) {
            const void* newline = std::memchr(data + pos, '\n', size - pos);
            if (newline != nullptr) {
                pos = static_cast<size_t>(static_cast<const char*>(newline) - data) + 1;
                return;
            }
            pos = size;
            if (!Refill()) return;
        }
    }

    // A bad line: thrown (strict) or counted (lenient, without allocating).
    void Issue(CandumpIssue issue, std::string_view what, std::string_view text) {
        if (config.mode == CandumpMode::kStrict) {
            const std::string detail =
                issue == CandumpIssue::kTooLong
                    ? "line longer than " + std::to_string(config.max_line_bytes) + " bytes"
                    : std::string(what);
            throw FileError(StatusCode::kParseError, name, line,
                            detail + ": '" + Excerpt(text) + "'");
        }
        ++stats.skipped[static_cast<size_t>(issue)];
    }
};

CandumpReader::CandumpReader(std::unique_ptr<State> state) : state_(std::move(state)) {}

CandumpReader::CandumpReader(const std::filesystem::path& path, const CandumpReaderConfig& config)
    : state_(std::make_unique<State>()) {
    config.Validate();
    State& s = *state_;
    s.name = path.string();
    s.config = config;
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
        throw FileError(StatusCode::kIoError, s.name, 0, "is a folder, not a candump log");
    }
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        const int err = errno;
        throw FileError(err == ENOENT ? StatusCode::kNotFound : StatusCode::kIoError, s.name, 0,
                        std::string("cannot open: ") + std::strerror(err));
    }
    s.gz = gzdopen(fd, "rb");
    if (s.gz == nullptr) {
        ::close(fd);
        throw FileError(StatusCode::kIoError, s.name, 0, "cannot open: zlib could not start");
    }
    gzbuffer(s.gz, 128 * 1024);
    s.buffer.resize(std::max(kMinBufferBytes, 2 * (config.max_line_bytes + 1)));
    s.data = s.buffer.data();
}

CandumpReader CandumpReader::FromMemory(std::string name, std::string_view text,
                                        const CandumpReaderConfig& config) {
    config.Validate();
    auto state = std::make_unique<State>();
    state->name = std::move(name);
    state->config = config;
    state->data = text.data();
    state->size = text.size();
    state->eof = true;
    return CandumpReader(std::move(state));
}

CandumpReader::CandumpReader(CandumpReader&&) noexcept = default;
CandumpReader& CandumpReader::operator=(CandumpReader&&) noexcept = default;
CandumpReader::~CandumpReader() = default;

bool CandumpReader::Next(CandumpRecord& record) {
    State& s = *state_;
    for (;;) {
        std::string_view text;
        bool terminated = true;
        const State::LineKind kind = s.NextLine(text, terminated);
        if (kind == State::LineKind::kEnd) return false;
        ++s.stats.lines;
        ++s.line;
        if (kind == State::LineKind::kTooLong) {
            s.Issue(CandumpIssue::kTooLong, "line longer than max_line_bytes", text);
            continue;
        }
        if (std::all_of(text.begin(), text.end(),
                        [](char c) { return c == ' ' || c == '\t' || c == '\r'; })) {
            ++s.stats.blank_lines;
            continue;
        }
        CandumpLine parsed;
        CandumpIssue issue = CandumpIssue::kGarbage;
        std::string_view what;
        if (!ParseCandumpLine(text, parsed, issue, what)) {
            if (!terminated) {
                // The cut last line of a killed recording.
                s.truncated = true;
                return false;
            }
            s.Issue(issue, what, text);
            continue;
        }
        if (s.have_last && parsed.frame.timestamp_ns < s.last_ns) {
            s.Issue(CandumpIssue::kBackwards, "timestamp earlier than the previous frame's", text);
            continue;
        }
        if (!terminated) s.stats.unterminated_last_line = true;
        s.have_last = true;
        s.last_ns = parsed.frame.timestamp_ns;
        ++s.stats.frames;
        record.frame = parsed.frame;
        record.interface_name = parsed.interface_name;
        record.line = s.line;
        return true;
    }
}

bool CandumpReader::truncated() const { return state_->truncated; }
const CandumpStats& CandumpReader::stats() const { return state_->stats; }
const std::string& CandumpReader::name() const { return state_->name; }
const CandumpReaderConfig& CandumpReader::config() const { return state_->config; }

// ---------------------------------------------------------------------------------------------
// Writer

void CandumpWriterConfig::Validate() const {
    if (seconds_width < 1 || seconds_width > 20) {
        throw Error(StatusCode::kInvalidArgument,
                    "seconds_width: " + std::to_string(seconds_width) + ", must be in [1, 20]");
    }
    if (interface_width < 0 || interface_width > 15) {
        throw Error(StatusCode::kInvalidArgument,
                    "interface_width: " + std::to_string(interface_width) + ", must be in [0, 15]");
    }
    if (buffer_bytes < kMaxCandumpLineBytes || buffer_bytes > (size_t{1} << 30)) {
        throw Error(StatusCode::kInvalidArgument,
                    "buffer_bytes: " + std::to_string(buffer_bytes) + ", must be in [" +
                        std::to_string(kMaxCandumpLineBytes) + ", 2^30]");
    }
}

CandumpWriter::CandumpWriter(const std::filesystem::path& path, const CandumpWriterConfig& config)
    : config_(config), name_(path.string()), path_(path) {
    config_.Validate();
    std::filesystem::path target = path;
    if (config_.atomic) {
        temporary_ = path;
        temporary_ += ".tmp." + std::to_string(::getpid());
        target = temporary_;
    }
    fd_ = ::open(target.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) {
        const int err = errno;
        Fail(config_.atomic ? "cannot create the temporary file " + temporary_.string()
                            : std::string("cannot create"),
             err);
    }
    buffer_.reserve(config_.buffer_bytes);
}

CandumpWriter::CandumpWriter(const CandumpWriterConfig& config, std::string name)
    : config_(config), name_(std::move(name)), memory_mode_(true) {
    config_.Validate();
}

CandumpWriter::~CandumpWriter() {
    if (fd_ < 0) return;
    if (config_.atomic) {
        // Never finished: the target keeps its old contents (or stays absent).
        ::close(fd_);
        ::unlink(temporary_.c_str());
        return;
    }
    try {
        Flush();
    } catch (const FileError&) {
        // Quietly: Close() is the place to see write errors.
    }
    ::close(fd_);
}

void CandumpWriter::Fail(const std::string& what, int error_number) const {
    throw FileError(StatusCode::kIoError, name_, 0,
                    error_number != 0 ? what + ": " + std::strerror(error_number) : what);
}

void CandumpWriter::Write(const CanFrame& frame, std::string_view interface_name) {
    if (closed_) Fail("write after Close()", 0);
    char line[kMaxCandumpLineBytes];
    const size_t n = FormatCandumpLine(frame, interface_name, line, config_.seconds_width,
                                       config_.interface_width);
    if (n == 0) {
        const char* problem = LineProblem(frame, interface_name);
        throw Error(StatusCode::kInvalidArgument, name_ + ": cannot write frame " +
                                                      std::to_string(frames_) + ": " +
                                                      (problem != nullptr ? problem : "unknown"));
    }
    Put(line, n);
    ++frames_;
}

void CandumpWriter::Put(const char* data, size_t size) {
    if (memory_mode_) {
        memory_.append(data, size);
        return;
    }
    if (buffer_.size() + size > config_.buffer_bytes) Flush();
    buffer_.append(data, size);
}

void CandumpWriter::Flush() {
    if (memory_mode_ || fd_ < 0) return;
    size_t done = 0;
    while (done < buffer_.size()) {
        const ssize_t n = ::write(fd_, buffer_.data() + done, buffer_.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            const int err = errno;
            buffer_.erase(0, done);
            Fail("write failed", err);
        }
        done += static_cast<size_t>(n);
    }
    buffer_.clear();
}

void CandumpWriter::Close() {
    if (closed_) return;
    if (memory_mode_) {
        closed_ = true;
        return;
    }
    Flush();
    const int fd = fd_;
    fd_ = -1;
    closed_ = true;
    auto fail = [&](const std::string& what) {
        const int err = errno;
        if (config_.atomic) ::unlink(temporary_.c_str());
        Fail(what, err);
    };
    if (::fsync(fd) != 0) {
        ::close(fd);
        fail("fsync failed");
    }
    if (::close(fd) != 0) fail("close failed");
    if (!config_.atomic) return;
    if (::rename(temporary_.c_str(), path_.c_str()) != 0) {
        fail("cannot rename the temporary file into place");
    }
    // The rename is durable once the folder entry is on disk.
    const std::filesystem::path dir =
        path_.has_parent_path() ? path_.parent_path() : std::filesystem::path(".");
    const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        ::fsync(dfd);
        ::close(dfd);
    }
}

}  // namespace bimslam::can
