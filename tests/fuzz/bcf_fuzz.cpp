// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// libFuzzer target: the BCF reader (host_tools/changes/bcf_reader.hpp) over a topic's XML.
// Mutating a zip's bytes mostly breaks its checksums, which libzip (not instrumented) refuses
// before our code runs; so the input is the topic's markup and viewpoint, split at the first
// "\0\0", and the target puts them in a zip beside a valid bcf.version (2.1 or 3.0, by the
// input's length) and a snapshot. Reading ends with topics or throws common::FileError naming
// the file; anything else (a crash, a sanitizer report, another exception, a topic without its
// Guid) is a finding. Seeds (corpus/bcf_fuzz): markup and viewpoint pairs our writer wrote, 2.1
// and 3.0, and buildingSMART's layout of several viewpoints and comments.
#include <zip.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "algorithms/common/status.hpp"
#include "host_tools/changes/bcf_reader.hpp"

namespace {

// A zip of the four entries, stored (libzip).
std::string Zip(std::string_view version, std::string_view markup, std::string_view visinfo) {
    zip_error_t error;
    zip_error_init(&error);
    zip_source_t* src = zip_source_buffer_create(nullptr, 0, 0, &error);
    zip_t* z = src ? zip_open_from_source(src, ZIP_TRUNCATE, &error) : nullptr;
    zip_error_fini(&error);
    if (!z) __builtin_trap();
    zip_source_keep(src);
    const std::string_view png("\x89PNG\r\n\x1a\n", 8);
    const std::pair<const char*, std::string_view> entries[] = {
        {"bcf.version", version},
        {"t/markup.bcf", markup},
        {"t/viewpoint.bcfv", visinfo},
        {"t/snapshot.png", png}};
    for (const auto& [name, bytes] : entries) {
        zip_source_t* s = zip_source_buffer(z, bytes.data(), bytes.size(), 0);
        if (!s || zip_file_add(z, name, s, 0) < 0) __builtin_trap();
    }
    if (zip_close(z) != 0) __builtin_trap();
    zip_stat_t st;
    std::string out;
    if (zip_source_stat(src, &st) == 0 && zip_source_open(src) == 0) {
        out.resize(size_t(st.size));
        zip_source_read(src, out.data(), st.size);
        zip_source_close(src);
    }
    zip_source_free(src);
    return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace bimslam;
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    const size_t split = input.find(std::string_view("\0\0", 2));
    const std::string_view markup = input.substr(0, split);
    const std::string_view visinfo =
        split == std::string_view::npos ? std::string_view() : input.substr(split + 2);
    const std::string_view version = size % 2 == 0
                                         ? R"(<?xml version="1.0"?><Version VersionId="2.1"/>)"
                                         : R"(<?xml version="1.0"?><Version VersionId="3.0"/>)";
    try {
        const change_detection::BcfFile f =
            change_detection::ReadBcfBytes("fuzz.bcf", Zip(version, markup, visinfo));
        for (const auto& t : f.topics) {
            if (t.topic.guid.empty()) __builtin_trap();  // a topic read without its Guid
            if (!t.viewpoints.empty() && t.topic.viewpoint.guid != t.viewpoints[0].guid)
                __builtin_trap();
        }
    } catch (const common::FileError& e) {
        if (e.path() != "fuzz.bcf") __builtin_trap();
    }
    return 0;
}
