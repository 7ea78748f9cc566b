// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Calendar time: ISO 8601 text to and from UNIX-epoch nanoseconds (the host clock's, HostTime),
// in UTC whatever the machine's time zone. `bimslam simulate --start` and `bimslam map`'s visits
// (their dates, from the recordings' first packets) read and write these.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace bimslam::common {

// UNIX-epoch nanoseconds from an ISO 8601 date or date-time (a subset): "2026-03-02",
// "2026-03-02T09:30", "2026-03-02T09:30:15", with fractional seconds, and "Z" or a "+hh:mm" /
// "-hh:mm" offset (none: UTC). Throws common::Error (kInvalidArgument) naming the text.
int64_t ParseUtcTime(std::string_view iso);
// "2026-03-02T09:30:15Z" (whole seconds, floored, UTC), and its day "2026-03-02".
std::string FormatUtcTime(int64_t unix_ns);
std::string FormatUtcDay(int64_t unix_ns);

}  // namespace bimslam::common
