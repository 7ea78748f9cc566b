// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/net/capture_file.hpp"

#include <fcntl.h>
#include <stdio_ext.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>

#include "algorithms/common/status.hpp"

namespace bimslam::net::detail {
namespace {

using common::FileError;
using common::StatusCode;

// The cookie of a gzip stream: zlib's handle, the decompressed position (for ftell) and what
// went wrong.
struct GzipCookie {
    gzFile gz = nullptr;
    int64_t position = 0;
    GzipStatus status;
};

ssize_t GzipRead(void* cookie, char* buffer, size_t size) {
    auto* c = static_cast<GzipCookie*>(cookie);
    const unsigned want = static_cast<unsigned>(std::min<size_t>(size, 1u << 30));
    const int got = gzread(c->gz, buffer, want);
    if (got < 0) {
        int code = Z_OK;
        const char* message = gzerror(c->gz, &code);
        if (code != Z_ERRNO) {
            c->status.error = message != nullptr ? message : "unknown zlib error";
            errno = EIO;
        }
        return -1;
    }
    if (got == 0) {
        // zlib reports a gzip stream cut off before its trailer as Z_BUF_ERROR and returns what
        // it could decompress: the same as a killed capture.
        int code = Z_OK;
        gzerror(c->gz, &code);
        if (code == Z_BUF_ERROR) c->status.cut = true;
    }
    c->position += got;
    return got;
}

// stdio asks for the position (ftell) and to go back to the start (rewind after peeking at the
// header); zlib seeks forward by decompressing and backward by starting again.
int GzipSeek(void* cookie, off64_t* offset, int whence) {
    auto* c = static_cast<GzipCookie*>(cookie);
    if (whence == SEEK_CUR && *offset == 0) {
        *offset = c->position;
        return 0;
    }
    const z_off_t at = gzseek(c->gz, static_cast<z_off_t>(*offset), whence);
    if (at < 0) {
        errno = EINVAL;
        return -1;
    }
    c->position = at;
    *offset = at;
    return 0;
}

int GzipClose(void* cookie) {
    auto* c = static_cast<GzipCookie*>(cookie);
    const int code = gzclose_r(c->gz);
    delete c;
    return code == Z_OK ? 0 : -1;
}

}  // namespace

void ThrowReadError(const std::string& name, const GzipStatus* gzip, uint64_t offset,
                    const std::string& reason) {
    if (gzip != nullptr && !gzip->error.empty()) {
        throw FileError(StatusCode::kParseError, name, 0,
                        "gzip data broken after byte " + std::to_string(offset) +
                            " (decompressed): " + gzip->error);
    }
    throw FileError(StatusCode::kIoError, name, 0,
                    "read failed after byte " + std::to_string(offset) + ": " + reason);
}

CaptureFile OpenCaptureFile(const std::filesystem::path& path, std::vector<char>& buffer) {
    // open() first so that errno names the reason.
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        const int err = errno;
        throw FileError(err == ENOENT ? StatusCode::kNotFound : StatusCode::kIoError, path.string(),
                        0, std::string("cannot open: ") + std::strerror(err));
    }
    unsigned char magic[2] = {};
    const bool gzip = ::pread(fd, magic, 2, 0) == 2 && magic[0] == 0x1F && magic[1] == 0x8B;
    CaptureFile out;
    if (!gzip) {
        out.file = ::fdopen(fd, "rb");
        if (out.file == nullptr) ::close(fd);
    } else {
        auto cookie = std::make_unique<GzipCookie>();
        cookie->gz = gzdopen(fd, "rb");
        if (cookie->gz == nullptr) {
            ::close(fd);
            throw FileError(StatusCode::kIoError, path.string(), 0, "cannot open (zlib)");
        }
        gzbuffer(cookie->gz, kStreamBufferBytes);
        out.file = fopencookie(cookie.get(), "rb", {GzipRead, nullptr, GzipSeek, GzipClose});
        if (out.file == nullptr) {
            gzclose_r(cookie->gz);
        } else {
            out.gzip = &cookie.release()->status;  // the close function deletes it
        }
    }
    if (out.file == nullptr) {
        throw FileError(StatusCode::kIoError, path.string(), 0,
                        std::string("cannot open: ") + std::strerror(errno));
    }
    buffer.resize(kStreamBufferBytes);
    std::setvbuf(out.file, buffer.data(), _IOFBF, buffer.size());
    // One reader uses the stream: no lock per fread (libpcap makes two per record).
    __fsetlocking(out.file, FSETLOCKING_BYCALLER);
    return out;
}

}  // namespace bimslam::net::detail
