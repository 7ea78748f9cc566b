// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Status and error types.
//
// Hot paths (per packet, per scan) return a Status and count faults; they never throw. Set-up,
// file parsing and host tools throw Error (or FileError, which names the file and line) carrying a
// message that says which field and which value were wrong.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

namespace bimslam::common {

enum class StatusCode : uint8_t {
    kOk = 0,
    kInvalidArgument,   // a caller passed something out of contract
    kParseError,        // input bytes or text do not follow their format
    kIoError,           // the operating system refused a read or write
    kNotFound,          // a file, key or element is missing
    kAlreadyExists,     // refusing to overwrite
    kOutOfRange,        // a value outside its documented range
    kDataLoss,          // input ended early or was cut off
    kDeadlineExceeded,  // a bounded-time computation ran out of budget
    kUnavailable,       // a resource (socket, device) is not there
    kInternal,          // a broken invariant: a bug
};

std::string_view ToString(StatusCode code);

// A status code plus a human message. An ok Status holds no message and does not allocate, so
// returning Status::Ok() from a hot path is free.
class [[nodiscard]] Status {
public:
    Status() = default;
    Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}
    static Status Ok() { return Status(); }

    bool ok() const { return code_ == StatusCode::kOk; }
    StatusCode code() const { return code_; }
    const std::string& message() const { return message_; }
    // "ok", or "<code>: <message>".
    std::string ToString() const;

private:
    StatusCode code_ = StatusCode::kOk;
    std::string message_;
};

// An exception carrying a StatusCode.
class Error : public std::runtime_error {
public:
    Error(StatusCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
    StatusCode code() const { return code_; }

private:
    StatusCode code_;
};

// An error in a file: what() reads "<path>:<line>: <message>" (", line" left out when 0), the
// form compilers use, so editors and terminals link it.
class FileError : public Error {
public:
    FileError(StatusCode code, std::string path, size_t line, const std::string& message);
    const std::string& path() const { return path_; }
    size_t line() const { return line_; }
    // The message without the path and line.
    const std::string& detail() const { return detail_; }

private:
    std::string path_;
    size_t line_;
    std::string detail_;
};

// The one check every ...Config::Validate() uses: throws Error(kInvalidArgument) with a message
// naming the struct, the field, the value and the rule (DESIGN.md, "Conventions").
inline void Require(bool ok, const char* config, const char* field, double value,
                    const char* rule) {
    if (!ok) {
        throw Error(StatusCode::kInvalidArgument, std::string(config) + "." + field + " = " +
                                                      std::to_string(value) + ": " + rule);
    }
}

// Throws Error(kInvalidArgument, message): a check of inputs that is not one field's rule.
[[noreturn]] inline void ThrowInvalid(const std::string& message) {
    throw Error(StatusCode::kInvalidArgument, message);
}

}  // namespace bimslam::common
