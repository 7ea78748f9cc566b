// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Line-oriented text parsing with errors that name the file and the line.
//
// Every text reader of the project (trajectories, Scan Context files, g2o, ASCII PCD and PLY)
// goes through this, so a malformed number, a non-finite value or a short line is reported the
// same way: common::FileError "<file>:<line>: <what was wrong>".
#pragma once

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "algorithms/common/status.hpp"

namespace bimslam::io {

// The whole token as a number of type T (std::from_chars: no locale, no leading space), a leading
// '+' allowed; false when the token is empty, is not a number or has characters after it.
template <typename T>
bool FromChars(std::string_view token, T& value) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty()) return false;
    const auto res = std::from_chars(token.data(), token.data() + token.size(), value);
    return res.ec == std::errc() && res.ptr == token.data() + token.size();
}

class LineReader {
public:
    // `path` is used in messages only; `text` must outlive the reader.
    LineReader(std::string path, std::string_view text, size_t first_line = 1);

    // The next line without its line end ("\n" or "\r\n"); false at the end of the text.
    bool Next(std::string_view& line);
    // Number of the line last returned by Next (1-based), or of the first line before any call.
    size_t line_number() const { return line_; }
    const std::string& path() const { return path_; }
    // Bytes of text not yet returned (for formats with a text header and a binary body).
    std::string_view Rest() const { return text_.substr(pos_); }

    // Throws common::FileError at the current line.
    [[noreturn]] void Fail(const std::string& message,
                           common::StatusCode code = common::StatusCode::kParseError) const;

    // Whitespace-separated tokens of `line`, into `out` (cleared first).
    static void Split(std::string_view line, std::vector<std::string_view>& out);

    // A finite number; `what` names the field in the message ("x", "qw", "cell (3, 12)").
    double ParseDouble(std::string_view token, std::string_view what) const;
    float ParseFloat(std::string_view token, std::string_view what) const;
    int64_t ParseInt(std::string_view token, std::string_view what) const;
    // Seconds with a decimal fraction, parsed exactly into nanoseconds ("1699999999.123456789").
    int64_t ParseSecondsToNs(std::string_view token, std::string_view what) const;

private:
    std::string path_;
    std::string_view text_;
    size_t pos_ = 0;
    size_t line_;
    size_t next_line_;
};

// "s.nnnnnnnnn": exact seconds from integer nanoseconds, the inverse of ParseSecondsToNs.
std::string FormatNsAsSeconds(int64_t ns);

}  // namespace bimslam::io
