// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/common/utc_time.hpp"

#include <ctime>

#include "algorithms/common/status.hpp"

namespace bimslam::common {

namespace {
constexpr int64_t kNsPerSecond = 1'000'000'000;

std::string Format(int64_t unix_ns, const char* format) {
    // Floored to the second (a time before 1970 too).
    const time_t s = time_t(unix_ns / kNsPerSecond - (unix_ns % kNsPerSecond < 0));
    std::tm tm{};
    gmtime_r(&s, &tm);
    char text[40];
    std::strftime(text, sizeof text, format, &tm);
    return text;
}
}  // namespace

int64_t ParseUtcTime(std::string_view iso) {
    const auto bad = [&](const char* why) {
        return Error(StatusCode::kInvalidArgument, "'" + std::string(iso) +
                                                       "': not an ISO 8601 date-time (" + why +
                                                       "; e.g. 2026-03-02T09:30:00Z)");
    };
    size_t i = 0;
    const auto digits = [&](size_t n) {
        int64_t v = 0;
        for (size_t k = 0; k < n; ++k, ++i) {
            if (i >= iso.size() || iso[i] < '0' || iso[i] > '9') throw bad("a digit expected");
            v = 10 * v + (iso[i] - '0');
        }
        return v;
    };
    const auto expect = [&](char c) {
        if (i >= iso.size() || iso[i] != c) throw bad("a separator expected");
        ++i;
    };
    const int64_t year = digits(4);
    expect('-');
    const int64_t month = digits(2);
    expect('-');
    const int64_t day = digits(2);
    if (month < 1 || month > 12 || day < 1 || day > 31) throw bad("no such month or day");
    int64_t seconds = 0, fraction_ns = 0;
    if (i < iso.size() && (iso[i] == 'T' || iso[i] == ' ')) {
        ++i;
        const int64_t hour = digits(2);
        expect(':');
        const int64_t minute = digits(2);
        int64_t second = 0;
        if (i < iso.size() && iso[i] == ':') {
            ++i;
            second = digits(2);
            if (i < iso.size() && (iso[i] == '.' || iso[i] == ',')) {
                ++i;
                int64_t scale = kNsPerSecond / 10;
                if (i >= iso.size() || iso[i] < '0' || iso[i] > '9') throw bad("a digit expected");
                for (; i < iso.size() && iso[i] >= '0' && iso[i] <= '9'; ++i, scale /= 10)
                    fraction_ns += (iso[i] - '0') * scale;
            }
        }
        if (hour > 23 || minute > 59 || second > 60) throw bad("no such time of day");
        seconds = hour * 3600 + minute * 60 + second;
        if (i < iso.size() && iso[i] == 'Z') {
            ++i;
        } else if (i < iso.size() && (iso[i] == '+' || iso[i] == '-')) {
            const int64_t sign = iso[i] == '+' ? 1 : -1;
            ++i;
            const int64_t oh = digits(2);
            expect(':');
            const int64_t om = digits(2);
            seconds -= sign * (oh * 3600 + om * 60);  // local = UTC + offset
        }
    }
    if (i != iso.size()) throw bad("unexpected text at the end");
    // timegm (glibc, the BSDs): the machine's time zone plays no part.
    std::tm tm{};
    tm.tm_year = int(year - 1900);
    tm.tm_mon = int(month - 1);
    tm.tm_mday = int(day);
    const int64_t midnight = int64_t(timegm(&tm));
    std::tm back{};
    const time_t t = time_t(midnight);
    gmtime_r(&t, &back);
    if (back.tm_mday != int(day)) throw bad("no such day in that month");
    return (midnight + seconds) * kNsPerSecond + fraction_ns;
}

std::string FormatUtcTime(int64_t unix_ns) { return Format(unix_ns, "%Y-%m-%dT%H:%M:%SZ"); }

std::string FormatUtcDay(int64_t unix_ns) { return Format(unix_ns, "%Y-%m-%d"); }

}  // namespace bimslam::common
