// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Counts heap allocations, to prove that hot paths do not allocate (DESIGN.md, "Hot path").
// Linking bimslam::test_allocation_counter replaces the global operator new of the whole test
// binary, so only dedicated test binaries link it.
#pragma once

#include <cstddef>

namespace bimslam::test {

// Calls of operator new (any form) since the program started.
size_t Allocations();

}  // namespace bimslam::test
