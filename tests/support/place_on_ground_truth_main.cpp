// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// place_on_ground_truth SESSION CAPTURE/ground_truth.tum OUT: a test tool (not installed) that
// writes SESSION placed on the simulator's ground truth as an anchored session would be
// (ground_truth_session.hpp), for running `bimslam changes` by hand before `bimslam anchor` exists.
#include <iostream>

#include "algorithms/common/status.hpp"
#include "tests/support/ground_truth_session.hpp"

int main(int argc, char** argv) {
    if (argc != 4 || std::string(argv[1]) == "--help") {
        std::cerr << "usage: place_on_ground_truth SESSION GROUND_TRUTH.tum OUT\n"
                     "  writes OUT: SESSION with frames.world = bim and every pose taken from the\n"
                     "  capture's ground truth at its exact stamp\n";
        return argc == 2 ? 0 : 2;
    }
    try {
        const auto r = bimslam::test::PlaceSessionOnGroundTruth(argv[1], argv[2], argv[3]);
        std::cout << argv[3] << ": " << r.keyframes << " keyframes, " << r.scans
                  << " scans placed on " << argv[2] << "\n";
        return 0;
    } catch (const bimslam::common::Error& e) {
        std::cerr << "place_on_ground_truth: error: " << e.what() << "\n";
        return 2;
    }
}
