// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// SHA-256 (FIPS 180-4), to name the exact BIM model a session was generated from
// (specs/session-data.md: session.json holds the model's sha256).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace bimslam::io {

// 64 lowercase hex digits.
std::string Sha256Hex(std::string_view bytes);
// Of a whole file, streamed; throws common::FileError naming the file.
std::string Sha256File(const std::filesystem::path& path);

}  // namespace bimslam::io
