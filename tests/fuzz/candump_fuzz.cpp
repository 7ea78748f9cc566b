// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// libFuzzer target: the candump log reader (drivers/can/candump.hpp) over arbitrary bytes, in both
// modes. Lenient reading of memory never throws; strict reading ends cleanly or throws
// common::FileError; every frame returned writes (FormatCandumpLine) and parses back to itself.
// Anything else (a crash, a sanitizer report, another exception, a broken invariant) is a finding.
// Seeds (corpus/candump_fuzz): small logs our CandumpWriter wrote.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "algorithms/common/status.hpp"
#include "drivers/can/candump.hpp"

namespace {

using bimslam::common::CanFrame;

bool SameFrame(const CanFrame& a, const CanFrame& b) {
    // The writer keeps microseconds, as candump does.
    return a.timestamp_ns / 1000 == b.timestamp_ns / 1000 && a.id == b.id &&
           a.extended == b.extended && a.remote == b.remote && a.error == b.error && a.fd == b.fd &&
           a.len == b.len && a.fd_flags == b.fd_flags && a.len8_dlc == b.len8_dlc &&
           a.data == b.data;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace bimslam;
    const std::string_view text(reinterpret_cast<const char*>(data), size);

    can::CandumpReaderConfig lenient;
    lenient.mode = can::CandumpMode::kLenient;
    lenient.max_line_bytes = can::kMaxCandumpLineBytes;  // the shortest limit: long lines too
    can::CandumpReader reader = can::CandumpReader::FromMemory("fuzz.log", text, lenient);
    can::CandumpRecord record;
    int64_t last_ns = INT64_MIN;
    while (reader.Next(record)) {
        const std::string_view name = record.interface_name;
        if (name.data() < text.data() || name.data() + name.size() > text.data() + text.size()) {
            __builtin_trap();  // a name outside the input
        }
        if (record.frame.timestamp_ns < last_ns) __builtin_trap();  // time order not kept
        last_ns = record.frame.timestamp_ns;
        if (common::CanFrameProblem(record.frame) != nullptr) __builtin_trap();
        char line[can::kMaxCandumpLineBytes];
        const size_t n = can::FormatCandumpLine(record.frame, name, line);
        if (n == 0 || line[n - 1] != '\n') __builtin_trap();
        can::CandumpLine again;
        can::CandumpIssue issue{};
        std::string_view what;
        if (!can::ParseCandumpLine(std::string_view(line, n - 1), again, issue, what) ||
            !SameFrame(again.frame, record.frame) || again.interface_name != name) {
            __builtin_trap();  // the writer wrote what the reader does not read back
        }
    }
    const can::CandumpStats& s = reader.stats();
    if (s.lines != s.frames + s.blank_lines + s.skipped_lines() + (reader.truncated() ? 1 : 0)) {
        __builtin_trap();  // a line neither returned nor counted
    }

    can::CandumpReaderConfig strict_config;
    strict_config.max_line_bytes = can::kMaxCandumpLineBytes;
    try {
        can::CandumpReader strict = can::CandumpReader::FromMemory("fuzz.log", text, strict_config);
        uint64_t frames = 0;
        while (strict.Next(record)) ++frames;
        // Strict got through: the lenient pass skipped nothing and returned the same frames.
        if (s.skipped_lines() != 0 || frames != s.frames) __builtin_trap();
    } catch (const common::FileError& e) {
        if (e.path() != "fuzz.log" || e.line() == 0 || s.skipped_lines() == 0) __builtin_trap();
    }
    return 0;
}
