// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// libFuzzer target: the rig map package's reader (algorithms/localization/rig_map.hpp), which the
// rig runs on a file from the host. The input's header is made to agree with it (size and both
// CRC-32s: tests/support/rig_map_bytes.hpp), or mutations would stop at the checksum. A package
// or common::FileError; anything else is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "algorithms/common/status.hpp"
#include "algorithms/localization/rig_map.hpp"
#include "tests/support/rig_map_bytes.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::string bytes(reinterpret_cast<const char*>(data), size);
    bimslam::test::MakeRigMapHeaderAgree(&bytes);
    try {
        bimslam::localization::ParseRigMap("fuzz.rigmap", bytes);
    } catch (const bimslam::common::FileError&) {
    }
    return 0;
}
