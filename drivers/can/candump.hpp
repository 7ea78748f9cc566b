// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// candump log files (`candump -l`, linux-can/can-utils), read and written.
//
// One frame a line (specs/go1-can.md, "Recording and replay"):
//   (1699999999.123456) can0 123#0011223344556677      classic, standard 11-bit id (3 hex digits)
//   (1699999999.123456) can0 12345678#00112233          extended 29-bit id (8 hex digits)
//   (1699999999.123456) can0 123#R   123#R8   123#R8_C   remote frame, optional DLC and raw DLC
//   (1699999999.123456) can0 123##1001122               CAN FD: "##", flags nibble, data
//   (1699999999.123456) can0 123#1122334455667788_C     classic 8 bytes sent with raw DLC 9..15
//   (1699999999.123456) can0 20000080#0000000000000000  error frame: 8 digits with the ERR flag
// candump writes "(%010ld.%06ld) %*s %s\n": seconds zero-padded to 10 digits, microseconds, the
// interface name right-aligned to the longest name on its command line, hex in upper case, and
// with `-x` a trailing " R" / " T" (received / transmitted). The reader also takes what other
// writers produce: unpadded seconds, 1 to 9 fraction digits (exact to the nanosecond), lower-case
// hex, '.' between data bytes, several spaces between fields, CR LF line ends. Blank lines are
// skipped and counted in both modes.
//
// Errors: strict mode (the default: a recording of ours must be perfect, and a damaged one is
// worth knowing about) throws common::FileError "<file>:<line>: <what>: '<the line>'" at the first
// bad line (a CandumpIssue below); the frames before it have been returned. Lenient mode (what the
// CLI and replay use) skips such lines and counts them by cause in CandumpStats::skipped. A
// timestamp earlier than the previous frame's is such an issue too (kBackwards); the next line is
// compared with the last frame returned. A last line without its '\n' that does not parse is what
// a killed candump leaves: it ends the file cleanly in both modes, and truncated() says so.
// Unreadable files and broken gzip data throw in both modes.
//
// Streaming: the reader holds one buffer (64 KiB or more), whatever the file size; `.gz` files are
// decompressed on the fly (zlib also reads plain files through the same calls). Next() does not
// allocate.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "algorithms/common/can_frame.hpp"

namespace bimslam::can {

// Why a line is not a frame.
enum class CandumpIssue : uint8_t {
    kGarbage,           // not "(<time>) <interface> <frame>": brackets, separators, extra text
    kBadTimestamp,      // not <digits>.<1..9 digits>, or beyond the int64 nanosecond range
    kMissingInterface,  // no interface name (or one longer than 15 characters, IFNAMSIZ - 1)
    kBadId,             // not 3 or 8 hex digits, a standard id above 7FF, flag bits in the id
    kNonHex,            // a data or flags character that is not a hex digit
    kOddHex,            // data with an odd number of hex digits
    kBadLength,         // classic > 8 bytes, CAN FD length no DLC gives, remote DLC > 8, raw DLC
    kBackwards,         // a timestamp earlier than the previous frame's
    kTooLong,           // a line longer than CandumpReaderConfig::max_line_bytes
    kUnsupported,       // CAN XL frames (CanFrame cannot hold them)
};
inline constexpr size_t kCandumpIssueCount = 10;
// "garbage", "bad timestamp", ...: for messages and reports.
std::string_view ToString(CandumpIssue issue);

// A parsed line. `interface_name` points into the parsed text.
struct CandumpLine {
    common::CanFrame frame;
    std::string_view interface_name;
};

// Parses one line (without its line end; a trailing '\r' is allowed). Returns true and fills
// `out`, or returns false and sets `issue` and `what` (a static description). Does not allocate
// or throw; does not check time order.
bool ParseCandumpLine(std::string_view line, CandumpLine& out, CandumpIssue& issue,
                      std::string_view& what);

// Longest line FormatCandumpLine writes (64 FD data bytes, padded names, 20-digit seconds).
inline constexpr size_t kMaxCandumpLineBytes = 256;

// One line as candump -l writes it, '\n' included, into `out`: the seconds zero-padded to
// `seconds_width` digits (candump: 10; 1 leaves them unpadded), the interface right-aligned to
// `interface_width`. Returns the bytes written, or 0 when the frame is not a valid CAN frame
// (common::CanFrameProblem), its timestamp is negative, the interface name is empty, longer than
// 15 characters or holds whitespace, or `out` is shorter than kMaxCandumpLineBytes. No allocation.
size_t FormatCandumpLine(const common::CanFrame& frame, std::string_view interface_name,
                         std::span<char> out, int seconds_width = 10, int interface_width = 0);

enum class CandumpMode : uint8_t {
    kStrict,   // the first bad line throws common::FileError naming the file and line
    kLenient,  // bad lines are skipped and counted by cause
};

struct CandumpReaderConfig {
    CandumpMode mode = CandumpMode::kStrict;
    // Longer lines are kTooLong (the longest real line is about 260 bytes).
    size_t max_line_bytes = 4096;

    // Throws common::Error (kInvalidArgument) naming the field.
    void Validate() const;
};

struct CandumpStats {
    uint64_t lines = 0;        // lines read, of every kind
    uint64_t frames = 0;       // frames returned
    uint64_t blank_lines = 0;  // empty or white space only: skipped in both modes
    std::array<uint64_t, kCandumpIssueCount> skipped{};  // lenient mode: lines skipped, by cause
    bool unterminated_last_line = false;  // the file's last line had no '\n' (it parsed)

    uint64_t skipped_lines() const;
    uint64_t skipped_by(CandumpIssue issue) const { return skipped[static_cast<size_t>(issue)]; }
};

// One frame of the log. `interface_name` points into the reader's buffer and stays valid until
// the next call to Next.
struct CandumpRecord {
    common::CanFrame frame;
    std::string_view interface_name;
    uint64_t line = 0;  // 1-based line number
};

class CandumpReader {
public:
    // Opens a log, gzip-compressed or not. Throws common::FileError naming the file when it cannot
    // be opened, common::Error for a bad configuration.
    explicit CandumpReader(const std::filesystem::path& path,
                           const CandumpReaderConfig& config = {});
    // Reads text the caller keeps alive (not gzip); `name` is used in error messages.
    static CandumpReader FromMemory(std::string name, std::string_view text,
                                    const CandumpReaderConfig& config = {});

    CandumpReader(CandumpReader&&) noexcept;
    CandumpReader& operator=(CandumpReader&&) noexcept;
    ~CandumpReader();

    // The next frame, or false at the end of the file. Strict mode throws common::FileError at a
    // bad line; both modes throw it when the file cannot be read or its gzip data is broken.
    bool Next(CandumpRecord& record);

    // The file ended inside a line that does not parse (a killed candump), or its gzip stream was
    // cut before the trailer.
    bool truncated() const;
    const CandumpStats& stats() const;
    const std::string& name() const;
    const CandumpReaderConfig& config() const;

private:
    struct State;
    explicit CandumpReader(std::unique_ptr<State> state);
    std::unique_ptr<State> state_;
};

struct CandumpWriterConfig {
    // true: the log goes to "<path>.tmp.<pid>", which Close() fsyncs and renames over `path`, so
    // `path` is never half-written (a writer destroyed without Close() removes the temporary
    // file). false: written in place as a stream, for long live recordings; the buffer holds whole
    // lines only, so a killed writer leaves a log that ends at a line end.
    bool atomic = true;
    int seconds_width = 10;   // candump: "%010ld"; 1 for unpadded seconds
    int interface_width = 0;  // candump: the longest interface name on its command line
    size_t buffer_bytes = 256 * 1024;

    // Throws common::Error (kInvalidArgument) naming the field.
    void Validate() const;
};

// Writes candump -l logs (see FormatCandumpLine) through a buffer.
class CandumpWriter {
public:
    // Creates the (temporary) file. Throws common::FileError naming the file.
    explicit CandumpWriter(const std::filesystem::path& path,
                           const CandumpWriterConfig& config = {});
    // Writes into memory (text()); `name` is used in messages.
    explicit CandumpWriter(const CandumpWriterConfig& config, std::string name = "<memory>");
    CandumpWriter(const CandumpWriter&) = delete;
    CandumpWriter& operator=(const CandumpWriter&) = delete;
    // Streaming mode: flushes quietly. Atomic mode: without Close(), removes the temporary file.
    ~CandumpWriter();

    // Appends one line. Throws common::Error (kInvalidArgument) naming the problem for a frame
    // FormatCandumpLine refuses, common::FileError naming the file when a flush fails.
    void Write(const common::CanFrame& frame, std::string_view interface_name);
    // Writes the buffered lines (streaming mode: to `path`; atomic mode: to the temporary file).
    void Flush();
    // Flush, fsync, close and (atomic mode) rename into place. Throws common::FileError naming the
    // file. Further writes are errors.
    void Close();

    // The log so far (memory writer).
    const std::string& text() const { return memory_; }
    uint64_t frames() const { return frames_; }
    const std::string& name() const { return name_; }

private:
    void Put(const char* data, size_t size);
    [[noreturn]] void Fail(const std::string& what, int error_number) const;

    CandumpWriterConfig config_;
    std::string name_;
    std::filesystem::path path_;
    std::filesystem::path temporary_;
    int fd_ = -1;
    bool memory_mode_ = false;
    bool closed_ = false;
    std::string buffer_;  // whole lines
    std::string memory_;
    uint64_t frames_ = 0;
};

}  // namespace bimslam::can
