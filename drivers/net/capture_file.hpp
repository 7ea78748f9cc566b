// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Internal to drivers/net: a stdio stream over a capture file, plain or gzip-compressed, the
// input of libpcap (which reads a FILE*) and of the pcapng block reader.
//
// A plain file is read as it is; a gzip file (magic 1F 8B, RFC 1952) through zlib behind
// fopencookie(3), so libpcap reads the decompressed bytes and ftell(3) counts them. Either way
// the stream reads through a buffer of kStreamBufferBytes the caller owns (fewer read(2) calls
// than stdio's 4 KiB default).
#pragma once

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace bimslam::net::detail {

inline constexpr size_t kStreamBufferBytes = 256 * 1024;

// What reading a gzip stream found wrong; stays valid until the stream is closed.
struct GzipStatus {
    bool cut = false;   // the stream ended before its trailer (a killed capture, a cut copy)
    std::string error;  // zlib's message when the compressed data is broken; empty otherwise
};

struct CaptureFile {
    FILE* file = nullptr;              // owned by the caller (fclose, or pcap_close after libpcap)
    const GzipStatus* gzip = nullptr;  // null for a plain file
};

// Opens `path` for reading through `buffer` (resized to kStreamBufferBytes; it must outlive the
// stream). Throws common::FileError naming the file (kNotFound when it does not exist).
CaptureFile OpenCaptureFile(const std::filesystem::path& path, std::vector<char>& buffer);

// Throws the common::FileError for a failed read (ferror) of a stream after decompressed byte
// `offset`: zlib's message for broken gzip data (kParseError), else `reason` (kIoError).
[[noreturn]] void ThrowReadError(const std::string& name, const GzipStatus* gzip, uint64_t offset,
                                 const std::string& reason);

// Owns a FILE* until it is released (to libpcap, which closes it in pcap_close).
struct FileCloser {
    void operator()(FILE* f) const {
        if (f != nullptr) std::fclose(f);
    }
};
using FilePtr = std::unique_ptr<FILE, FileCloser>;

}  // namespace bimslam::net::detail
