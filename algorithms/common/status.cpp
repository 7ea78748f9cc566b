// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/common/status.hpp"

namespace bimslam::common {

std::string_view ToString(StatusCode code) {
    switch (code) {
        case StatusCode::kOk:
            return "ok";
        case StatusCode::kInvalidArgument:
            return "invalid argument";
        case StatusCode::kParseError:
            return "parse error";
        case StatusCode::kIoError:
            return "I/O error";
        case StatusCode::kNotFound:
            return "not found";
        case StatusCode::kAlreadyExists:
            return "already exists";
        case StatusCode::kOutOfRange:
            return "out of range";
        case StatusCode::kDataLoss:
            return "data loss";
        case StatusCode::kDeadlineExceeded:
            return "deadline exceeded";
        case StatusCode::kUnavailable:
            return "unavailable";
        case StatusCode::kInternal:
            return "internal error";
    }
    return "unknown status";
}

std::string Status::ToString() const {
    if (ok()) return "ok";
    return std::string(common::ToString(code_)) + ": " + message_;
}

namespace {
std::string FileMessage(const std::string& path, size_t line, const std::string& message) {
    std::string out = path;
    if (line > 0) out += ":" + std::to_string(line);
    return out + ": " + message;
}
}  // namespace

FileError::FileError(StatusCode code, std::string path, size_t line, const std::string& message)
    : Error(code, FileMessage(path, line, message)),
      path_(std::move(path)),
      line_(line),
      detail_(message) {}

}  // namespace bimslam::common
