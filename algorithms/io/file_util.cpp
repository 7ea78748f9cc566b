// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/file_util.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>

#include "algorithms/common/status.hpp"

namespace bimslam::io {
namespace {
using common::FileError;
using common::StatusCode;

[[noreturn]] void ThrowErrno(const std::filesystem::path& path, const std::string& what) {
    const int err = errno;
    throw FileError(err == ENOENT ? StatusCode::kNotFound : StatusCode::kIoError, path.string(), 0,
                    what + ": " + std::strerror(err));
}

// RAII file descriptor; closes on scope exit.
struct Fd {
    int fd = -1;
    ~Fd() {
        if (fd >= 0) ::close(fd);
    }
};
}  // namespace

std::string ReadFileToString(const std::filesystem::path& path) {
    Fd f;
    f.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (f.fd < 0) ThrowErrno(path, "cannot open");
    std::string out;
    std::array<char, 1 << 16> buf{};
    for (;;) {
        const ssize_t n = ::read(f.fd, buf.data(), buf.size());
        if (n < 0) {
            if (errno == EINTR) continue;
            ThrowErrno(path, "cannot read");
        }
        if (n == 0) break;
        out.append(buf.data(), static_cast<size_t>(n));
    }
    return out;
}

void WriteFileAtomic(const std::filesystem::path& path, std::string_view bytes, Sync sync) {
    bool given = false;
    WriteFileAtomic(
        path,
        [&]() {
            if (given) return std::string_view();
            given = true;
            return bytes;
        },
        sync);
}

void WriteFileAtomic(const std::filesystem::path& path,
                     const std::function<std::string_view()>& next, Sync sync) {
    const std::filesystem::path dir =
        path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
    std::filesystem::path tmp = path;
    tmp += ".tmp." + std::to_string(::getpid());
    {
        Fd f;
        f.fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
        if (f.fd < 0) ThrowErrno(path, "cannot create temporary file " + tmp.string());
        for (;;) {
            std::string_view bytes;
            try {
                bytes = next();
            } catch (...) {
                ::unlink(tmp.c_str());
                throw;
            }
            if (bytes.empty()) break;
            size_t done = 0;
            while (done < bytes.size()) {
                const ssize_t n = ::write(f.fd, bytes.data() + done, bytes.size() - done);
                if (n < 0) {
                    if (errno == EINTR) continue;
                    const int err = errno;
                    ::unlink(tmp.c_str());
                    errno = err;
                    ThrowErrno(path, "cannot write");
                }
                done += static_cast<size_t>(n);
            }
        }
        if (sync == Sync::kNow && ::fsync(f.fd) != 0) {
            const int err = errno;
            ::unlink(tmp.c_str());
            errno = err;
            ThrowErrno(path, "cannot fsync");
        }
    }
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        const int err = errno;
        ::unlink(tmp.c_str());
        errno = err;
        ThrowErrno(path, "cannot rename the temporary file into place");
    }
    if (sync == Sync::kDeferred) return;
    // The rename itself is durable only once the folder entry is on disk.
    Fd d;
    d.fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (d.fd >= 0) ::fsync(d.fd);
}

void SyncFileSystem(const std::filesystem::path& dir) {
    Fd d;
    d.fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (d.fd < 0 || ::syncfs(d.fd) != 0) ThrowErrno(dir, "cannot sync the file system");
}

namespace {
template <typename T>
std::string Format(T v) {
    std::array<char, 64> buf{};
    const auto res = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    return std::string(buf.data(), res.ptr);
}
}  // namespace

std::string FormatDouble(double v) { return Format(v); }
std::string FormatFloat(float v) { return Format(v); }

}  // namespace bimslam::io
