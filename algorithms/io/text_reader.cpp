// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/text_reader.hpp"

#include <charconv>
#include <cmath>
#include <limits>

namespace bimslam::io {
namespace {
using common::FileError;
using common::StatusCode;

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v'; }

std::string Quote(std::string_view token) {
    constexpr size_t kMax = 40;  // garbage input must not flood the message
    std::string out = "'";
    out.append(token.substr(0, kMax));
    if (token.size() > kMax) out += "...";
    return out + "'";
}

}  // namespace

LineReader::LineReader(std::string path, std::string_view text, size_t first_line)
    : path_(std::move(path)), text_(text), line_(first_line), next_line_(first_line) {}

bool LineReader::Next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const size_t end = text_.find('\n', pos_);
    const size_t stop = end == std::string_view::npos ? text_.size() : end;
    line = text_.substr(pos_, stop - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end == std::string_view::npos ? text_.size() : end + 1;
    line_ = next_line_++;
    return true;
}

void LineReader::Fail(const std::string& message, StatusCode code) const {
    throw FileError(code, path_, line_, message);
}

void LineReader::Split(std::string_view line, std::vector<std::string_view>& out) {
    out.clear();
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && IsSpace(line[i])) ++i;
        const size_t start = i;
        while (i < line.size() && !IsSpace(line[i])) ++i;
        if (i > start) out.push_back(line.substr(start, i - start));
    }
}

double LineReader::ParseDouble(std::string_view token, std::string_view what) const {
    double v = 0.0;
    if (!FromChars(token, v)) Fail(std::string(what) + ": " + Quote(token) + " is not a number");
    if (!std::isfinite(v)) Fail(std::string(what) + ": " + Quote(token) + " is not finite");
    return v;
}

float LineReader::ParseFloat(std::string_view token, std::string_view what) const {
    float v = 0.0f;
    if (!FromChars(token, v)) Fail(std::string(what) + ": " + Quote(token) + " is not a number");
    if (!std::isfinite(v)) Fail(std::string(what) + ": " + Quote(token) + " is not finite");
    return v;
}

int64_t LineReader::ParseInt(std::string_view token, std::string_view what) const {
    int64_t v = 0;
    if (!FromChars(token, v)) {
        Fail(std::string(what) + ": " + Quote(token) + " is not an integer");
    }
    return v;
}

int64_t LineReader::ParseSecondsToNs(std::string_view token, std::string_view what) const {
    // Exact path for plain decimals: integer seconds and up to 9 fraction digits, rounded on the
    // tenth. A double would lose ~240 ns at UNIX-epoch magnitudes.
    std::string_view t = token;
    bool negative = false;
    if (!t.empty() && (t.front() == '-' || t.front() == '+')) {
        negative = t.front() == '-';
        t.remove_prefix(1);
    }
    const size_t dot = t.find('.');
    const std::string_view int_part = t.substr(0, dot);
    const std::string_view frac_part =
        dot == std::string_view::npos ? std::string_view() : t.substr(dot + 1);
    auto all_digits = [](std::string_view s) {
        for (char c : s) {
            if (c < '0' || c > '9') return false;
        }
        return true;
    };
    if (!int_part.empty() && int_part.size() <= 10 && all_digits(int_part) &&
        all_digits(frac_part) && !(int_part.empty() && frac_part.empty())) {
        int64_t sec = 0;
        for (char c : int_part) sec = sec * 10 + (c - '0');
        int64_t frac = 0;
        for (size_t i = 0; i < 9; ++i) {
            frac = frac * 10 + (i < frac_part.size() ? frac_part[i] - '0' : 0);
        }
        if (frac_part.size() > 9 && frac_part[9] >= '5') ++frac;
        constexpr int64_t kMaxSeconds = std::numeric_limits<int64_t>::max() / 1'000'000'000 - 1;
        if (sec > kMaxSeconds) Fail(std::string(what) + ": " + Quote(token) + " is out of range");
        const int64_t ns = sec * 1'000'000'000 + frac;
        return negative ? -ns : ns;
    }
    // Anything else (exponents, "1e9") goes through a double.
    const double s = ParseDouble(token, what);
    if (std::fabs(s) > 9.2e9) Fail(std::string(what) + ": " + Quote(token) + " is out of range");
    return static_cast<int64_t>(std::llround(s * 1e9));
}

std::string FormatNsAsSeconds(int64_t ns) {
    const bool negative = ns < 0;
    const uint64_t a = negative ? static_cast<uint64_t>(-(ns + 1)) + 1 : static_cast<uint64_t>(ns);
    const uint64_t sec = a / 1'000'000'000;
    const uint64_t frac = a % 1'000'000'000;
    std::string f = std::to_string(frac);
    f.insert(0, 9 - f.size(), '0');
    return (negative ? "-" : "") + std::to_string(sec) + "." + f;
}

}  // namespace bimslam::io
