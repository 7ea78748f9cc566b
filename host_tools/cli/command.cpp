// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/cli/command.hpp"

#include <iomanip>
#include <iostream>
#include <sstream>

#include "algorithms/common/status.hpp"

namespace bimslam::cli {

int Run(const std::function<int()>& body) {
    using common::StatusCode;
    try {
        return body();
    } catch (const common::Error& e) {
        std::cerr << "bimslam: error: " << e.what() << "\n";
        // Input that is missing, malformed, cut off or in the way is the user's to fix (2);
        // anything else failed while working (1).
        switch (e.code()) {
            case StatusCode::kInvalidArgument:
            case StatusCode::kParseError:
            case StatusCode::kNotFound:
            case StatusCode::kDataLoss:
            case StatusCode::kAlreadyExists:
            case StatusCode::kOutOfRange:
                return kExitBadInput;
            default:
                return kExitFailure;
        }
    } catch (const std::exception& e) {
        std::cerr << "bimslam: error: " << e.what() << "\n";
        return kExitFailure;
    }
}

std::string Fixed(double v, int digits) {
    std::ostringstream s;
    s << std::fixed << std::setprecision(digits) << v;
    return s.str();
}

}  // namespace bimslam::cli
