// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/cli/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <iostream>

namespace bimslam::cli {

ProgressBar::ProgressBar(bool enabled) : enabled_(enabled) {}

ProgressBar::~ProgressBar() { Clear(); }

bool ProgressBar::Terminal() { return ::isatty(STDERR_FILENO) != 0; }

void ProgressBar::Update(std::string_view stage, double fraction) {
    if (!enabled_) return;
    const int percent = std::clamp(int(fraction * 100), 0, 100);
    if (percent == percent_ && stage == stage_) return;
    percent_ = percent;
    stage_ = stage;
    constexpr int kWidth = 30;
    const int filled = percent * kWidth / 100;
    std::cerr << "\r\033[K  " << stage << " [" << std::string(size_t(filled), '#')
              << std::string(size_t(kWidth - filled), ' ') << "] " << percent << " %" << std::flush;
    shown_ = true;
}

void ProgressBar::Clear() {
    if (!shown_) return;
    std::cerr << "\r\033[K" << std::flush;
    shown_ = false;
    percent_ = -1;
}

}  // namespace bimslam::cli
