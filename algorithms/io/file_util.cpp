// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/file_util.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>

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

namespace {
// Writes all of [data, data + size) at the file's offset; false with errno set on failure.
bool WriteAll(int fd, const char* data, size_t size) {
    while (size > 0) {
        const ssize_t n = ::write(fd, data, size);
        if (n < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        data += n;
        size -= static_cast<size_t>(n);
    }
    return true;
}

// A streamed write's pieces into a file. With O_DIRECT, which needs the buffer, the length and
// the file offset aligned (open(2), "O_DIRECT"), they are gathered in an aligned buffer and
// written a whole number of blocks at a time; the last partial block goes through the page cache.
// 4096 bytes serve logical blocks of 512 and 4096 bytes; a file system that wants more refuses
// the write with EINVAL, and the rest goes through the page cache.
class PieceWriter {
public:
    PieceWriter(int fd, bool direct) : fd_(fd), direct_(direct) {
        if (direct_) staged_.reset(static_cast<char*>(std::aligned_alloc(kAlign, kStage)));
        if (direct_ && !staged_) Buffered();
    }

    bool Write(std::string_view piece) {
        if (!direct_) return WriteAll(fd_, piece.data(), piece.size());
        while (!piece.empty()) {
            const size_t n = std::min(piece.size(), kStage - used_);
            std::memcpy(staged_.get() + used_, piece.data(), n);
            used_ += n;
            piece.remove_prefix(n);
            if (used_ == kStage && !Flush(kStage)) return false;
        }
        return true;
    }

    // What is still staged: its whole blocks directly, the rest through the page cache.
    bool Finish() {
        if (!direct_) return true;
        const size_t whole = used_ / kAlign * kAlign;
        if (whole > 0 && !Flush(whole)) return false;
        if (used_ == 0) return true;
        Buffered();
        return WriteAll(fd_, staged_.get(), used_);
    }

private:
    static constexpr size_t kAlign = 4096;
    static constexpr size_t kStage = size_t(8) << 20;

    // Writes the first `bytes` staged (a multiple of kAlign) and keeps the rest at the front.
    bool Flush(size_t bytes) {
        ssize_t n;
        do {
            n = ::write(fd_, staged_.get(), bytes);
        } while (n < 0 && errno == EINTR);
        if (n < 0 && errno == EINVAL && direct_) {  // alignment refused: the page cache
            Buffered();
            n = WriteAll(fd_, staged_.get(), bytes) ? ssize_t(bytes) : -1;
        }
        if (n < 0) return false;
        if (size_t(n) < bytes && !WriteAll(fd_, staged_.get() + n, bytes - size_t(n))) {
            return false;  // a short direct write: the rest buffered (offset now unaligned)
        }
        std::memmove(staged_.get(), staged_.get() + bytes, used_ - bytes);
        used_ -= bytes;
        return true;
    }

    void Buffered() {
        if (!direct_) return;
        const int flags = ::fcntl(fd_, F_GETFL);
        if (flags >= 0) ::fcntl(fd_, F_SETFL, flags & ~O_DIRECT);
        direct_ = false;
    }

    struct Free {
        void operator()(char* p) const { std::free(p); }
    };
    int fd_;
    bool direct_;
    std::unique_ptr<char, Free> staged_;
    size_t used_ = 0;
};
}  // namespace

void WriteFileAtomic(const std::filesystem::path& path,
                     const std::function<std::string_view()>& next, Sync sync, Cache cache) {
    const std::filesystem::path dir =
        path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
    std::filesystem::path tmp = path;
    tmp += ".tmp." + std::to_string(::getpid());
    {
        constexpr int kFlags = O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC;
        const bool direct = cache == Cache::kBypass;
        Fd f;
        f.fd = ::open(tmp.c_str(), kFlags | (direct ? O_DIRECT : 0), 0644);
        const bool opened_direct = direct && f.fd >= 0;
        if (f.fd < 0 && direct && errno == EINVAL) f.fd = ::open(tmp.c_str(), kFlags, 0644);
        if (f.fd < 0) ThrowErrno(path, "cannot create temporary file " + tmp.string());
        PieceWriter writer(f.fd, opened_direct);
        const auto fail = [&](const char* what) {
            const int err = errno;
            ::unlink(tmp.c_str());
            errno = err;
            ThrowErrno(path, what);
        };
        for (;;) {
            std::string_view bytes;
            try {
                bytes = next();
            } catch (...) {
                ::unlink(tmp.c_str());
                throw;
            }
            if (bytes.empty()) break;
            if (!writer.Write(bytes)) fail("cannot write");
        }
        if (!writer.Finish()) fail("cannot write");
        if (sync == Sync::kNow && ::fsync(f.fd) != 0) fail("cannot fsync");
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

AppendFile::AppendFile(std::filesystem::path path) : path_(std::move(path)) {
    fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0644);
    if (fd_ < 0) ThrowErrno(path_, "cannot create");
}

AppendFile::~AppendFile() { ::close(fd_); }

void AppendFile::Append(std::string_view bytes, Sync sync) {
    if (!WriteAll(fd_, bytes.data(), bytes.size())) {
        // What went in of a failed append (a full disk) is cut off again: the next append must
        // not follow half a line.
        const int err = errno;
        (void)::ftruncate(fd_, static_cast<off_t>(size_));
        errno = err;
        ThrowErrno(path_, "cannot append");
    }
    size_ += bytes.size();
    if (sync == Sync::kDeferred) return;
    if (::fdatasync(fd_) != 0) ThrowErrno(path_, "cannot fdatasync");
    if (entry_synced_) return;
    const std::filesystem::path dir =
        path_.has_parent_path() ? path_.parent_path() : std::filesystem::path(".");
    Fd d;
    d.fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    entry_synced_ = d.fd >= 0 && ::fsync(d.fd) == 0;
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
