// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Whole-file reads, atomic writes and exact number formatting shared by every reader and writer.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace bimslam::io {

// The whole file as bytes. Throws common::FileError naming the file when it is missing (kNotFound)
// or unreadable (kIoError).
std::string ReadFileToString(const std::filesystem::path& path);

// Writes bytes so that `path` is either its old self or complete, never half-written
// (specs/session-data.md, "Rules"): a temporary file in the same folder, fsync, rename over the
// target, fsync of the folder. Throws common::FileError (kIoError) naming the file on failure,
// and leaves no temporary file behind.
//
// Sync::kDeferred skips both fsyncs: the rename still keeps readers from ever seeing a half-written
// file, but after a power loss the file may be missing or empty until SyncFileSystem() has run.
// For offline writers of many files (a BIM reference session), which sync once at the end.
enum class Sync { kNow, kDeferred };
void WriteFileAtomic(const std::filesystem::path& path, std::string_view bytes,
                     Sync sync = Sync::kNow);
// The same, the bytes made piece by piece: `next` is called until it returns an empty view, each
// piece written before the next is asked for (a large file without all of it in memory). An
// exception from `next` leaves no temporary file behind and reaches the caller as it is.
//
// Cache::kBypass writes the pieces with O_DIRECT (open(2)): from this process's memory to the disk,
// not through the page cache. For files of hundreds of MB written once (a map's LAS): on the
// project's 2-core VM, copying 440 MB into the page cache took 1.0-2.4 s of kernel time, and
// O_DIRECT writes with the fsync 0.2-0.3 s (algorithms/io/README.md, "Large files"). Where the
// file system refuses O_DIRECT (tmpfs) or a write's alignment, the page cache is used.
enum class Cache { kPage, kBypass };
void WriteFileAtomic(const std::filesystem::path& path,
                     const std::function<std::string_view()>& next, Sync sync = Sync::kNow,
                     Cache cache = Cache::kPage);

// A file that grows at its end: a session's line files, which a recorder extends every few
// seconds for hours (rewriting them whole, as WriteFileAtomic would, costs memory and disk
// writes that grow with the session). The constructor creates the file empty (or empties it);
// Append writes the bytes at its end and, with Sync::kNow, fdatasync(2)s them (the folder's
// entry too, the first time). A failed append is cut back off the file, so the file holds only
// whole appends; but a power cut during an append can leave part of it on disk, so readers of
// such files drop a last line without its newline when they recover a cut-off session
// (algorithms/io/README.md, "Writing"). Throws common::FileError naming the file on failure.
class AppendFile {
public:
    explicit AppendFile(std::filesystem::path path);
    ~AppendFile();
    AppendFile(const AppendFile&) = delete;
    AppendFile& operator=(const AppendFile&) = delete;

    void Append(std::string_view bytes, Sync sync);
    size_t size() const { return size_; }

private:
    std::filesystem::path path_;
    int fd_ = -1;
    size_t size_ = 0;
    bool entry_synced_ = false;
};

// Flushes everything written to the file system holding `dir` (syncfs(2)). Throws
// common::FileError (kIoError) naming the folder on failure.
void SyncFileSystem(const std::filesystem::path& dir);

// Shortest decimal text that reads back to the same value (std::to_chars), so text round trips
// are bit-exact. Non-finite values print as nan, inf, -inf.
std::string FormatDouble(double v);
std::string FormatFloat(float v);

}  // namespace bimslam::io
