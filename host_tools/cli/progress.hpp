// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A progress bar on stderr for the `bimslam` commands that take more than a few seconds: one line
// redrawn in place ("\r"), only when stderr is a terminal (never in logs or pipes), at most when
// the shown percentage or stage changes.
#pragma once

#include <string>
#include <string_view>

namespace bimslam::cli {

class ProgressBar {
public:
    // enabled: false draws nothing (e.g. --json, or not a terminal: see Terminal()).
    explicit ProgressBar(bool enabled);
    ~ProgressBar();  // clears the line
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;

    // "  stage [#########           ] 45 %", fraction in [0, 1].
    void Update(std::string_view stage, double fraction);
    // Erases the bar (before printing results).
    void Clear();

    // True when stderr is a terminal.
    static bool Terminal();

private:
    bool enabled_;
    bool shown_ = false;
    std::string stage_;
    int percent_ = -1;
};

}  // namespace bimslam::cli
